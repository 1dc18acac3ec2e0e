#include "gapchain/observers.hpp"

#include "detail/check.hpp"
#include "detail/hermite.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gapchain {

MaxForceTracker::MaxForceTracker(const Dynamics& dyn, long split_period)
    : m_dyn(dyn), m_max(dyn.gaps()), m_gap(dyn.gaps()), m_rate(dyn.gaps()),
      m_scratch(dyn.dimension()), m_split_period(split_period) {}

void MaxForceTracker::on_step(const StepView& step) {
    const int n = m_dyn.bodies();
    const int gaps = m_dyn.gaps();
    const double h = step.t1 - step.t0;
    // Values at the start are those the previous step ended on, unless the run restarted.
    const bool continuous = m_have_previous && m_last_t == step.t0;
    double ground0 = 0.0, ground1 = 0.0;
    bool have_ground = false;
    for (int j = 0; j < gaps; ++j) {
        const double g0 = continuous ? m_gap[j] : m_dyn.gap(j, step.y0);
        const double r0 = continuous ? m_rate[j] : m_dyn.gap_rate(j, step.y0 + n);
        const double g1 = m_dyn.gap(j, step.y1);
        const double r1 = m_dyn.gap_rate(j, step.y1 + n);
        // The gap on this step as a quintic (value, rate, acceleration at both ends); the
        // ground terms are shared by every contact of the step.
        auto gap_interpolant = [&](int contact) {
            if (!have_ground) {
                ground0 = m_dyn.ground(step.t0);
                ground1 = m_dyn.ground(step.t1);
                have_ground = true;
            }
            return detail::QuinticHermite(g0, r0, m_dyn.gap_acceleration(contact, ground0, step.y0),
                                          g1, r1, m_dyn.gap_acceleration(contact, ground1, step.y1),
                                          h);
        };
        m_gap[j] = g1;
        m_rate[j] = r1;
        if (!step.recording) continue;

        ContactMaximum& best = m_max[j];
        double& half = m_half_max[step.period < m_split_period ? 0 : 1];
        double peak = g1;
        double peak_t = step.t1;
        if (!continuous && g0 > peak) {
            peak = g0;
            peak_t = step.t0;
        }
        // A maximum inside the step: the gap rate turns from closing to opening. The bound
        // (twice the tangent-intersection bound of a concave gap) keeps the interpolation to
        // the steps where the peak can be a penetration at all, and, once there are records,
        // to the peaks that could beat the contact's record or its half of the window's (the
        // second half starts below the first's records), or that may hide a brief contact.
        const double bound = std::max(g0, g1) + 0.5 * h * (r0 - r1);
        if (r0 > 0.0 && r1 < 0.0 && bound > 0.0 &&
            ((g0 <= 0.0 && g1 <= 0.0) || m_dyn.dissipative_contacts() ||
             m_dyn.force_at_penetration(j, bound) > std::min(best.force, half))) {
            const detail::QuinticHermite g = gap_interpolant(j);
            double tau = g.stationary_point(0.0, h);
            double inner = g.value(tau);
            // A scheme with dense output (exact) gives the peak to round-off: Newton on the
            // gap rate, started from the interpolant's peak.
            if (step.stepper != nullptr &&
                step.stepper->dense_state(step.t0 + tau, m_scratch.data())) {
                for (int it = 0; it < 6; ++it) {
                    const double t = step.t0 + tau;
                    step.stepper->dense_state(t, m_scratch.data());
                    const double rate = m_dyn.gap_rate(j, m_scratch.data() + n);
                    const double acc = m_dyn.gap_acceleration(j, m_dyn.ground(t), m_scratch.data());
                    if (acc >= 0.0) break;
                    const double dt = -rate / acc;
                    tau = std::clamp(tau + dt, 0.0, h);
                    if (std::abs(dt) <= 1e-14 * (1.0 + std::abs(t))) break;
                }
                step.stepper->dense_state(step.t0 + tau, m_scratch.data());
                inner = m_dyn.gap(j, m_scratch.data());
            }
            if (inner > peak) {
                peak = inner;
                peak_t = step.t0 + tau;
            }
            if (g0 <= 0.0 && g1 <= 0.0 && inner > 0.0) ++best.impacts; // closed and reopened
        }
        if (g0 <= 0.0 && g1 > 0.0) ++best.impacts;
        double force = m_dyn.force_at_penetration(j, peak);
        if (m_dyn.dissipative_contacts() && (peak > 0.0 || (!continuous && g0 > 0.0))) {
            // Hunt-Crossley: damping adds to the force while the contact closes, so the force
            // peaks before the deepest penetration. Maximise it on the step's interpolant:
            // a grid, then golden-section search around the best grid point.
            const detail::QuinticHermite g = gap_interpolant(j);
            auto f = [&](double tau) {
                return m_dyn.force_at_penetration(j, g.value(tau), g.rate(tau));
            };
            constexpr int grid = 16;
            double best_tau = h;
            force = f(h);
            for (int k = continuous ? 1 : 0; k < grid; ++k) {
                const double tau = h * k / grid;
                const double value = f(tau);
                if (value > force) {
                    force = value;
                    best_tau = tau;
                }
            }
            double lo = std::max(0.0, best_tau - h / grid), hi = std::min(h, best_tau + h / grid);
            const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
            for (int it = 0; it < 40 && hi - lo > 1e-14 * h; ++it) {
                const double a = hi - golden * (hi - lo), b = lo + golden * (hi - lo);
                if (f(a) > f(b))
                    hi = b;
                else
                    lo = a;
            }
            const double refined = f(0.5 * (lo + hi));
            if (refined > force) {
                best_tau = 0.5 * (lo + hi);
                force = refined;
            }
            peak_t = step.t0 + best_tau;
        }
        if (force > best.force) {
            best.force = force;
            best.time = peak_t;
        }
        half = std::max(half, force);
    }
    m_last_t = step.t1;
    m_have_previous = true;
}

double MaxForceTracker::max_force() const {
    double f = 0.0;
    for (const auto& c : m_max)
        f = std::max(f, c.force);
    return f;
}

SteadyStateDetector::SteadyStateDetector(int dimension, int max_period, double tolerance,
                                         long earliest_stop)
    : m_dim(dimension), m_max_period(max_period), m_tolerance(tolerance),
      m_earliest_stop(earliest_stop),
      m_ring(static_cast<std::size_t>(max_period) + 2, std::vector<double>(dimension)) {
    detail::require_range("run.max_steady_period", max_period, 1, 1000);
    detail::require_range("run.steady_tolerance", tolerance, 0.0, 1.0, detail::Bound::open_low);
}

bool SteadyStateDetector::matches(long a, long b) const {
    const auto& ya = m_ring[a % m_ring.size()];
    const auto& yb = m_ring[b % m_ring.size()];
    double scale = 1.0;
    double diff = 0.0;
    for (int i = 0; i < m_dim; ++i) {
        scale = std::max(scale, std::abs(ya[i]));
        diff = std::max(diff, std::abs(ya[i] - yb[i]));
    }
    return diff <= m_tolerance * scale;
}

bool SteadyStateDetector::on_period(long n, double t, const double* y) {
    std::copy(y, y + m_dim, m_ring[n % m_ring.size()].begin());
    if (m_period) return n >= m_earliest_stop + *m_period;
    for (int k = 1; k <= m_max_period; ++k) {
        if (n - 1 - k < 0) break;
        if (matches(n, n - k) && matches(n - 1, n - 1 - k)) {
            m_period = k;
            m_time = t;
            break;
        }
    }
    return m_period.has_value() && n >= m_earliest_stop + *m_period;
}

TrajectoryRecorder::TrajectoryRecorder(int every, TrajectorySink sink)
    : m_every(every), m_sink(std::move(sink)) {
    detail::require_range("output.decimate", every, 1, 1'000'000);
}

void TrajectoryRecorder::on_step(const StepView& step) {
    if (!step.recording) return;
    if (m_count == 0) m_sink(step.t0, step.y0);
    if (++m_count % m_every == 0) m_sink(step.t1, step.y1);
}

} // namespace gapchain
