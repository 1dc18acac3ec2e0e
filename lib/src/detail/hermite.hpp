#pragma once
// Quintic Hermite interpolation of a scalar on one step, from its value, first and second
// derivatives at both ends. Dense output between steps: its error is O(h^6) where the signal
// is smooth, far below the schemes' own error, so peaks and crossings located on it are
// located "to the integrator's accuracy" rather than at step points.

#include <algorithm>
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
    // Second derivative at tau.
    [[nodiscard]] double acceleration(double tau) const {
        const double s = tau / m_h;
        double r = 20.0 * m_c[5];
        for (int k = 4; k >= 2; --k)
            r = r * s + k * (k - 1) * m_c[k];
        return r / (m_h * m_h);
    }
    // Root of rate() in [lo, hi] where rate changes sign, to full precision.
    [[nodiscard]] double stationary_point(double lo, double hi) const {
        return root([this](double tau) { return rate(tau); },
                    [this](double tau) { return acceleration(tau); }, lo, hi);
    }
    // Root of value() - level in [lo, hi] where it changes sign, to full precision.
    [[nodiscard]] double crossing(double level, double lo, double hi) const {
        return root([this, level](double tau) { return value(tau) - level; },
                    [this](double tau) { return rate(tau); }, lo, hi);
    }

private:
    // Newton's method kept inside a shrinking sign-change bracket (as in Numerical Recipes'
    // rtsafe): a Newton step that leaves the bracket, or that is not less than half the step
    // before last, is replaced by bisection. The bracket guarantees convergence; Newton makes
    // it a handful of polynomial evaluations instead of the ~50 of plain bisection, which
    // matters because this runs once per contact switch and once per force peak.
    template <typename F, typename D>
    [[nodiscard]] double root(F f, D df, double lo, double hi) const {
        // Signs as the callers test them: zero counts as not positive (a gap of exactly 0
        // is open), so a bracket starting on a zero still looks for the sign change.
        const bool lo_positive = f(lo) > 0.0;
        double x = 0.5 * (lo + hi);
        double step = hi - lo, step_before = step;
        for (int it = 0; it < 100 && hi - lo > 1e-15 * m_h; ++it) {
            const double fx = f(x);
            if ((fx > 0.0) == lo_positive)
                lo = x;
            else
                hi = x;
            const double d = df(x);
            const double newton = d != 0.0 ? x - fx / d : lo - 1.0;
            // A Newton step below the tolerance (an exact simple zero gives a step of 0) is the
            // root: bisecting on from there, as the loop once did, took ~20 more evaluations to
            // shrink the bracket around a point already known (11 per root on average, now
            // 3-4). A zero where the value only touches 0 (d = 0) is no crossing: the search
            // goes on to the sign change, as the convention above says.
            if (d != 0.0 && std::abs(newton - x) <= 1e-15 * m_h) return std::clamp(newton, lo, hi);
            const double next =
                (newton > lo && newton < hi && std::abs(newton - x) <= 0.5 * std::abs(step_before))
                    ? newton
                    : 0.5 * (lo + hi);
            step_before = step;
            step = next - x;
            x = next;
            if (std::abs(step) <= 1e-15 * m_h) break;
        }
        return x;
    }

    double m_h;
    std::array<double, 6> m_c{};
};

} // namespace gapchain::detail
