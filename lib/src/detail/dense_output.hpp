#pragma once
// The whole state between the two ends of a step, by quintic Hermite interpolation of every
// displacement (u, v, a) and every velocity (v, a, jerk). Costs four O(Nm) evaluations to
// build, so it is built only for the steps where a section point or an event falls.

#include "detail/hermite.hpp"
#include "gapchain/dynamics.hpp"
#include "gapchain/run.hpp"

#include <vector>

namespace gapchain::detail {

class StepInterpolant {
public:
    StepInterpolant(const Dynamics& dyn, const StepView& step)
        : m_n(dyn.bodies()), m_t0(step.t0), m_h(step.t1 - step.t0) {
        const int n = m_n;
        std::vector<double> a0(n), a1(n), j0(n), j1(n);
        dyn.acceleration(dyn.ground(step.t0), step.y0, step.y0 + n, a0.data());
        dyn.acceleration(dyn.ground(step.t1), step.y1, step.y1 + n, a1.data());
        dyn.acceleration_rate(step.t0, step.y0, a0.data(), j0.data());
        dyn.acceleration_rate(step.t1, step.y1, a1.data(), j1.data());
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
    int m_n;
    double m_t0;
    double m_h;
    std::vector<QuinticHermite> m_parts;
};

} // namespace gapchain::detail
