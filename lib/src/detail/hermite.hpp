#pragma once
// Quintic Hermite interpolation of a scalar on one step, from its value, first and second
// derivatives at both ends. Dense output between steps: its error is O(h^6) where the signal
// is smooth, far below the schemes' own error, so peaks and crossings located on it are
// located "to the integrator's accuracy" rather than at step points.

#include <array>
#include <cmath>

namespace gapchain::detail {

class QuinticHermite {
public:
    // x0, x1: values; d0, d1: first derivatives; a0, a1: second derivatives; h: step length.
    QuinticHermite(double x0, double d0, double a0, double x1, double d1, double a1, double h)
        : m_h(h) {
        const double c0 = x0, c1 = h * d0, c2 = 0.5 * h * h * a0;
        const double r0 = x1 - c0 - c1 - c2;
        const double r1 = h * d1 - c1 - 2.0 * c2;
        const double r2 = h * h * a1 - 2.0 * c2;
        m_c = {c0,
               c1,
               c2,
               10.0 * r0 - 4.0 * r1 + 0.5 * r2,
               -15.0 * r0 + 7.0 * r1 - r2,
               6.0 * r0 - 3.0 * r1 + 0.5 * r2};
    }
    // Value at time tau in [0, h] from the start of the step.
    [[nodiscard]] double value(double tau) const {
        const double s = tau / m_h;
        double r = m_c[5];
        for (int k = 4; k >= 0; --k)
            r = r * s + m_c[k];
        return r;
    }
    // First derivative at tau.
    [[nodiscard]] double rate(double tau) const {
        const double s = tau / m_h;
        double r = 5.0 * m_c[5];
        for (int k = 4; k >= 1; --k)
            r = r * s + k * m_c[k];
        return r / m_h;
    }
    // Root of rate() in [lo, hi] where rate changes sign (bisection to full precision).
    [[nodiscard]] double stationary_point(double lo, double hi) const {
        return bisect([this](double tau) { return rate(tau); }, lo, hi);
    }
    // Root of value() - level in [lo, hi] where it changes sign.
    [[nodiscard]] double crossing(double level, double lo, double hi) const {
        return bisect([this, level](double tau) { return value(tau) - level; }, lo, hi);
    }

private:
    template <typename F>
    [[nodiscard]] double bisect(F f, double lo, double hi) const {
        double f_lo = f(lo);
        for (int it = 0; it < 60 && hi - lo > 1e-15 * m_h; ++it) {
            const double mid = 0.5 * (lo + hi);
            const double f_mid = f(mid);
            if ((f_mid > 0.0) == (f_lo > 0.0)) {
                lo = mid;
                f_lo = f_mid;
            } else {
                hi = mid;
            }
        }
        return 0.5 * (lo + hi);
    }

    double m_h;
    std::array<double, 6> m_c{};
};

} // namespace gapchain::detail
