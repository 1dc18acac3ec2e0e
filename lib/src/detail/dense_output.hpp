#pragma once
// The whole state between the two ends of a step, by quintic Hermite interpolation of every
// displacement (u, v, a) and every velocity (v, a, jerk). Costs four O(Nm) evaluations to
// build, so it is built only for the steps where a section point or an event falls.

#include "detail/hermite.hpp"
#include "gapchain/dynamics.hpp"
#include "gapchain/run.hpp"

#include <cmath>
#include <vector>

namespace gapchain::detail {

class StepInterpolant {
public:
    StepInterpolant(const Dynamics& dyn, const StepView& step)
        : m_n(dyn.bodies()), m_t0(step.t0), m_h(step.t1 - step.t0) {
        const int n = m_n;
        std::vector<double> a0(n), a1(n), j0(n), j1(n);
        const double inside0 = inside_offset(dyn, step.y0, step.y1, m_h);
        const double inside1 = inside_offset(dyn, step.y1, step.y0, -m_h);
        end_derivatives(dyn, step.t0, step.y0, inside0, a0, j0);
        end_derivatives(dyn, step.t1, step.y1, inside1, a1, j1);
        m_parts.reserve(2 * n);
        for (int i = 0; i < n; ++i)
            m_parts.emplace_back(step.y0[i], step.y0[n + i], a0[i], step.y1[i], step.y1[n + i],
                                 a1[i], m_h);
        for (int i = 0; i < n; ++i)
            m_parts.emplace_back(step.y0[n + i], a0[i], j0[i], step.y1[n + i], a1[i], j1[i], m_h);
    }
    // State at reduced time t in [t0, t1] into out (2 Nm entries).
    void state(double t, double* out) const {
        for (int i = 0; i < 2 * m_n; ++i)
            out[i] = m_parts[i].value(t - m_t0);
    }
    // Interpolant of state component i (0 <= i < 2 Nm), in time from the step start.
    [[nodiscard]] const QuinticHermite& component(int i) const { return m_parts[i]; }
    [[nodiscard]] double start() const { return m_t0; }
    [[nodiscard]] double length() const { return m_h; }

private:
    // How far into the step (reduced time, signed along `toward`, the step's length h reaching
    // from y_end to y_other) an end's derivatives are read: 0, or just past where a gap that is
    // on the surface at the end, or on the other side of it from the step's interior, switches.
    // Steps end on contact switches, located to about 1e-6 of a step of 0.009 on the
    // interpolant (rk8pd with run.step 0.02 on Fig 13's row at f_r = 3.0: g3 -3.1e-6 at the
    // end, open, closed inside). Read at the end, the jerk came from the other side's
    // configuration (under the linear law it jumps there by the contact stiffness times the gap
    // rate; the acceleration is continuous under every law), and the velocities' interpolant
    // was 2.8e-3 off: an event section on v4 found dips that never happen (a
    // reviewer's probe, helper-78). The interior's side of a gap is read at the step's middle
    // on the cubic through the ends' values and rates. An offset above 1e-3 of the step is no
    // switch at the end (a graze inside): none.
    static double inside_offset(const Dynamics& dyn, const double* y_end, const double* y_other,
                                double toward) {
        const int n = dyn.bodies();
        const double h = std::abs(toward);
        double offset = 0.0;
        for (int j = 0; j <= n; ++j) {
            const double g = dyn.gap(j, y_end), r = dyn.gap_rate(j, y_end + n);
            const double g_other = dyn.gap(j, y_other), r_other = dyn.gap_rate(j, y_other + n);
            // Rates along the step from this end: the cubic's middle, (g + g')/2 + h (r - r')/8.
            const double middle = 0.5 * (g + g_other) + 0.125 * toward * (r - r_other);
            const bool on_surface = std::abs(g) <= 1e-9 * std::abs(r) * h;
            if (!on_surface && (g > 0.0) == (middle > 0.0)) continue;
            const double past = 2.0 * std::abs(g) / std::max(std::abs(r), 1e-300) + 1e-6 * h;
            if (past <= 1e-3 * h) offset = std::max(offset, past);
        }
        return toward > 0.0 ? offset : -offset;
    }

    // The accelerations a and their rates at an end (time t, state y), read `offset` into the
    // step (inside_offset()) on the end's tangent.
    static void end_derivatives(const Dynamics& dyn, double t, const double* y, double offset,
                                std::vector<double>& a, std::vector<double>& jerk) {
        const int n = dyn.bodies();
        if (offset == 0.0) {
            dyn.acceleration(dyn.ground(t), y, y + n, a.data());
            dyn.acceleration_rate(t, y, a.data(), jerk.data());
            return;
        }
        std::vector<double> inside(y, y + 2 * n);
        for (int i = 0; i < n; ++i)
            inside[static_cast<std::size_t>(i)] += offset * y[n + i];
        dyn.acceleration(dyn.ground(t + offset), inside.data(), inside.data() + n, a.data());
        dyn.acceleration_rate(t + offset, inside.data(), a.data(), jerk.data());
    }

    int m_n;
    double m_t0;
    double m_h;
    std::vector<QuinticHermite> m_parts;
};

} // namespace gapchain::detail
