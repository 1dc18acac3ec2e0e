#pragma once
// An independent reference for the tests: the reduced equations of MODEL.md §2 written out
// again here (not through gapchain::Dynamics) and integrated with GSL's adaptive rk8pd at a
// tight tolerance. F_m is read on a fine uniform sampling refined by a parabola through the
// three samples around each maximum.

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace reference {

struct Row {
    int Nm;
    double fc, eps, e_r, f_r;
    double amplitude = 1.0;
};

inline double contact_k(const Row& r, int j) {
    return (j == 0 || j == r.Nm) ? r.fc : r.fc / 2.0;
}

inline double gap(const Row& r, int j, const double* u) {
    if (j == 0) return -u[0] - r.e_r;
    if (j == r.Nm) return u[r.Nm - 1] - r.e_r;
    return u[j - 1] - u[j] - r.e_r;
}

inline int rhs(double t, const double y[], double f[], void* params) {
    const Row& r = *static_cast<const Row*>(params);
    const double pi = std::numbers::pi;
    const int n = r.Nm;
    for (int i = 0; i < n; ++i) {
        const double pl = std::max(gap(r, i, y), 0.0);
        const double pr = std::max(gap(r, i + 1, y), 0.0);
        f[i] = y[n + i];
        f[n + i] = -4 * pi * r.eps * y[n + i] - 4 * pi * pi * y[i] -
                   4 * pi * pi * r.amplitude * std::cos(2 * pi * r.f_r * t) +
                   4 * pi * pi * (contact_k(r, i) * pl - contact_k(r, i + 1) * pr);
    }
    return GSL_SUCCESS;
}

struct Outcome {
    double F_m = 0.0;
    std::vector<double> contact_max; // per contact j = 0 .. Nm, the largest reduced force
    std::vector<double> state;       // at the end
};

// Integrates `periods` forcing periods from y0 (empty: rest); F_m over periods >= transient.
inline Outcome run(const Row& r, int periods, int transient = 0, std::vector<double> y0 = {},
                   int samples_per_period = 4000, double tol = 1e-12) {
    const int dim = 2 * r.Nm;
    if (y0.empty()) y0.assign(dim, 0.0);
    gsl_odeiv2_system sys{rhs, nullptr, static_cast<size_t>(dim), const_cast<Row*>(&r)};
    const double T = 1.0 / r.f_r;
    const double dt = T / samples_per_period;
    gsl_odeiv2_driver* d = gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd, dt, tol, tol);
    gsl_odeiv2_driver_set_hmax(d, dt);
    std::vector<double> y = y0;
    double t = 0.0;
    Outcome out;
    out.contact_max.assign(r.Nm + 1, 0.0);
    std::vector<double> prev2(r.Nm + 1, -1e300), prev1(r.Nm + 1, -1e300);
    const long total = static_cast<long>(periods) * samples_per_period;
    for (long k = 1; k <= total; ++k) {
        const double t_next = k * dt;
        gsl_odeiv2_driver_apply(d, &t, t_next, y.data());
        const bool recording = k > static_cast<long>(transient) * samples_per_period;
        for (int j = 0; j <= r.Nm; ++j) {
            const double g = gap(r, j, y.data());
            // Parabola through (prev2, prev1, g) when prev1 is a local maximum.
            if (recording && prev1[j] > 0.0 && prev1[j] >= prev2[j] && prev1[j] >= g) {
                const double a = 0.5 * (prev2[j] + g) - prev1[j];
                const double b = 0.5 * (g - prev2[j]);
                const double peak = a < 0.0 ? prev1[j] - b * b / (4.0 * a) : prev1[j];
                const double force = contact_k(r, j) * peak / std::sqrt(r.fc);
                out.contact_max[j] = std::max(out.contact_max[j], force);
                out.F_m = std::max(out.F_m, force);
            }
            prev2[j] = prev1[j];
            prev1[j] = g;
        }
    }
    gsl_odeiv2_driver_free(d);
    out.state = y;
    return out;
}

} // namespace reference
