#include "gapchain/observers.hpp"

#include "detail/check.hpp"
#include "detail/hermite.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>

namespace gapchain {

MaxForceTracker::MaxForceTracker(const Dynamics& dyn, long split_period)
    : m_dyn(dyn), m_max(dyn.gaps()), m_gap(dyn.gaps()), m_rate(dyn.gaps()), m_gap_next(dyn.gaps()),
      m_rate_next(dyn.gaps()), m_active(dyn.gaps()), m_flag(dyn.gaps()),
      m_threshold(dyn.gaps(), 0.0), m_scratch(dyn.dimension()), m_split_period(split_period) {}

namespace {

/// A contact's gap and gap rate at both ends of a step.
struct GapEnds {
    double g0, r0, g1, r1;
};

/// A value reached inside or at an end of a step, and the reduced time it is reached.
struct PeakAt {
    double value;
    double t;
};

/// One step as MaxForceTracker scans it, contact by contact: the peaks of a contact's gap and
/// force over the step. Holds references only, so that a step allocates nothing.
class StepScan {
public:
    /// continuous: the step starts where the previous one ended. scratch: 2 Nm entries.
    StepScan(const Dynamics& dyn, const StepView& step, bool continuous, double* scratch)
        : m_dyn(dyn), m_step(step), m_h(step.t1 - step.t0), m_continuous(continuous),
          m_scratch(scratch) {}
    /// The largest force of contact j over the step and when; adds to impacts a contact that
    /// closes and reopens inside the step (MaxForceTracker counts those closed at its end).
    /// record: the smallest force that could still count.
    PeakAt force_peak(int j, const GapEnds& e, double record, long& impacts);

private:
    /// Contact j's gap over the step as a quintic (value, rate, acceleration at both ends).
    detail::QuinticHermite gap_interpolant(int j, const GapEnds& e);
    /// The largest gap (deepest penetration) of contact j over the step, and when.
    PeakAt gap_peak(int j, const GapEnds& e, double record, long& impacts);
    /// The maximum of g, the gap of contact j, inside the step (its rate turns from > 0 to < 0).
    PeakAt inner_gap_peak(int j, const detail::QuinticHermite& g);
    /// Whether contact j, closed at both ends of the step, opens inside it (its gap dips below
    /// 0 between a falling and a rising end): then it closed again, an impact.
    bool opens_inside(int j, const GapEnds& e);
    /// The largest Hunt-Crossley force of contact j over the step, and when.
    PeakAt dissipative_force_peak(int j, const GapEnds& e);

    const Dynamics& m_dyn;
    const StepView& m_step;
    double m_h;
    bool m_continuous;
    double* m_scratch;
    double m_ground0 = 0.0;
    double m_ground1 = 0.0;
    bool m_have_ground = false;
};

detail::QuinticHermite StepScan::gap_interpolant(int j, const GapEnds& e) {
    // The ground terms are shared by every contact of the step, and most steps need none.
    if (!m_have_ground) {
        m_ground0 = m_dyn.ground(m_step.t0);
        m_ground1 = m_dyn.ground(m_step.t1);
        m_have_ground = true;
    }
    return detail::QuinticHermite(e.g0, e.r0, m_dyn.gap_acceleration(j, m_ground0, m_step.y0), e.g1,
                                  e.r1, m_dyn.gap_acceleration(j, m_ground1, m_step.y1), m_h);
}

PeakAt StepScan::force_peak(int j, const GapEnds& e, double record, long& impacts) {
    const PeakAt gap = gap_peak(j, e, record, impacts);
    if (m_dyn.dissipative_contacts() && (gap.value > 0.0 || (!m_continuous && e.g0 > 0.0)))
        return dissipative_force_peak(j, e);
    return {m_dyn.force_at_penetration(j, gap.value), gap.t};
}

PeakAt StepScan::gap_peak(int j, const GapEnds& e, double record, long& impacts) {
    PeakAt peak{e.g1, m_step.t1};
    if (!m_continuous && e.g0 > peak.value) peak = {e.g0, m_step.t0};
    // A maximum inside the step: the gap rate turns from closing to opening. The bound
    // (twice the tangent-intersection bound of a concave gap) keeps the interpolation to
    // the steps where the peak can be a penetration at all, and, once there are records,
    // to the peaks that could beat the contact's record or its half of the window's (the
    // second half starts below the first's records), or that may hide a brief contact.
    const bool open_at_both_ends = e.g0 <= 0.0 && e.g1 <= 0.0;
    const double bound = std::max(e.g0, e.g1) + 0.5 * m_h * (e.r0 - e.r1);
    if (e.r0 > 0.0 && e.r1 < 0.0 && bound > 0.0 &&
        (open_at_both_ends || m_dyn.dissipative_contacts() ||
         m_dyn.force_at_penetration(j, bound) > record)) {
        const PeakAt inner = inner_gap_peak(j, gap_interpolant(j, e));
        if (inner.value > peak.value) peak = inner;
        if (open_at_both_ends && inner.value > 0.0) ++impacts; // closed and reopened
    }
    if (opens_inside(j, e)) ++impacts;
    return peak;
}

bool StepScan::opens_inside(int j, const GapEnds& e) {
    // The mirror of gap_peak()'s bound: a convex dip lies above twice the tangent-intersection
    // bound. Like that bound it assumes the gap's curvature has one sign over the step; a
    // closed contact's ends are concave (its spring pushes back), and at h omega <= 0.4 the
    // curvature term is about 0.5 % of the gap. A step split at a switch starts or ends on the
    // surface, where the bound is negative and the interpolant is always read. A step split at the
    // contact's switches ends on a gap of 0 to round-off, which falls on either side; only where
    // both ends fell on the closed side does the reclosing go uncounted by the open-to-closed test
    // of list_contacts_to_scan().
    if (!(e.g0 > 0.0 && e.g1 > 0.0 && e.r0 < 0.0 && e.r1 > 0.0)) return false;
    if (std::min(e.g0, e.g1) - 0.5 * m_h * (e.r1 - e.r0) >= 0.0) return false;
    const detail::QuinticHermite g = gap_interpolant(j, e);
    const double tau = g.stationary_point(0.0, m_h);
    // A scheme with dense output gives the gap at the dip to round-off.
    if (m_step.stepper != nullptr && m_step.stepper->dense_state(m_step.t0 + tau, m_scratch))
        return m_dyn.gap(j, m_scratch) < 0.0;
    return g.value(tau) < 0.0;
}

PeakAt StepScan::inner_gap_peak(int j, const detail::QuinticHermite& g) {
    const int n = m_dyn.bodies();
    const double t0 = m_step.t0;
    const Stepper* stepper = m_step.stepper;
    double tau = g.stationary_point(0.0, m_h);
    // A scheme with dense output (exact) gives the peak to round-off: Newton on the gap rate,
    // started from the interpolant's peak.
    if (stepper == nullptr || !stepper->dense_state(t0 + tau, m_scratch))
        return {g.value(tau), t0 + tau};
    for (int it = 0; it < 6; ++it) {
        const double t = t0 + tau;
        stepper->dense_state(t, m_scratch);
        const double rate = m_dyn.gap_rate(j, m_scratch + n);
        const double acc = m_dyn.gap_acceleration(j, m_dyn.ground(t), m_scratch);
        if (acc >= 0.0) break;
        const double dt = -rate / acc;
        tau = std::clamp(tau + dt, 0.0, m_h);
        if (std::abs(dt) <= 1e-14 * (1.0 + std::abs(t))) break;
    }
    stepper->dense_state(t0 + tau, m_scratch);
    return {m_dyn.gap(j, m_scratch), t0 + tau};
}

// Hunt-Crossley: damping adds to the force while the contact closes, so the force peaks
// before the deepest penetration. Maximise it on the step's interpolant: a grid, then
// golden-section search around the best grid point.
PeakAt StepScan::dissipative_force_peak(int j, const GapEnds& e) {
    const double h = m_h;
    const detail::QuinticHermite g = gap_interpolant(j, e);
    auto f = [&](double tau) { return m_dyn.force_at_penetration(j, g.value(tau), g.rate(tau)); };
    constexpr int grid = 16;
    double best_tau = h;
    double force = f(h);
    for (int k = m_continuous ? 1 : 0; k < grid; ++k) {
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
    return {force, m_step.t0 + best_tau};
}

} // namespace

int MaxForceTracker::list_contacts_to_scan(double h) {
    const int gaps = m_dyn.gaps();
    // Most contacts cannot reach their record within most steps: open at both ends and
    // not closing in between, or closed but short of the record (the bound of gap_peak()
    // on the deepest penetration). A branch-free pass counts the closings and lists the
    // others, so that the scan's branches run on those few only. Thresholds set from the
    // step's first records only ever lie below the current ones, and gap_peak() checks
    // again: the answer is the one a scan of every contact gives.
    const double* g0 = m_gap.data();
    const double* r0 = m_rate.data();
    const double* g1 = m_gap_next.data();
    const double* r1 = m_rate_next.data();
    const double* threshold = m_threshold.data();
    double* flag = m_flag.data();
    const double half_h = 0.5 * h;
    // Every condition is a 0/1 double combined by arithmetic: no branch and no short circuit, so
    // that g++ vectorises the pass (with -fno-trapping-math, lib/CMakeLists.txt).
    for (int j = 0; j < gaps; ++j) {
        const double turning = (r0[j] > 0.0 ? 1.0 : 0.0) * (r1[j] < 0.0 ? 1.0 : 0.0);
        const double reach = std::max(g0[j], g1[j]) + turning * (half_h * (r0[j] - r1[j]));
        const double open_at_start = g0[j] <= 0.0 ? 1.0 : 0.0;
        const double open_at_both_ends = open_at_start * (g1[j] <= 0.0 ? 1.0 : 0.0);
        const double open_turning = turning * open_at_both_ends * (reach > 0.0 ? 1.0 : 0.0);
        // Closed at both ends but dipping below 0 between (opens_inside()): an impact to count.
        const double closed_at_both_ends = (1.0 - open_at_start) * (g1[j] > 0.0 ? 1.0 : 0.0);
        const double dip = std::min(g0[j], g1[j]) - half_h * (r1[j] - r0[j]);
        const double dipping = closed_at_both_ends * (r0[j] < 0.0 ? 1.0 : 0.0) *
                               (r1[j] > 0.0 ? 1.0 : 0.0) * (dip < 0.0 ? 1.0 : 0.0);
        const double scan =
            std::max(std::max(reach > threshold[j] ? 1.0 : 0.0, open_turning), dipping);
        const double closing = open_at_start * (g1[j] > 0.0 ? 1.0 : 0.0);
        flag[j] = scan + 2.0 * closing;
    }
    int active = 0;
    for (int j = 0; j < gaps; ++j) {
        const int code = static_cast<int>(flag[j]);
        m_max[j].impacts += code >> 1;
        m_active[active] = j;
        active += code & 1;
    }
    return active;
}

void MaxForceTracker::on_step(const StepView& step) {
    const int n = m_dyn.bodies();
    // Values at the start are those the previous step ended on, unless the run restarted.
    const bool continuous = m_have_previous && m_last_t == step.t0;
    if (!continuous) {
        m_dyn.gaps(step.y0, m_gap.data());
        m_dyn.gap_rates(step.y0 + n, m_rate.data());
    }
    m_dyn.gaps(step.y1, m_gap_next.data());
    m_dyn.gap_rates(step.y1 + n, m_rate_next.data());
    m_last_t = step.t1;
    m_have_previous = true;
    if (step.recording) {
        const int half_index = step.period < m_split_period ? 0 : 1;
        if (step.period != m_period) {
            start_period(step.period);
            set_thresholds(half_index);
        } else if (half_index != m_threshold_half) {
            set_thresholds(half_index);
        }
        const int active = list_contacts_to_scan(step.t1 - step.t0);
        // The window's first step counts its start too: a contact in progress there, its
        // force falling, peaked at the window's start (Fig 13's row at f_r = 4.0, 100 periods
        // discarded: exact read "no contact", rk4 1.4e-6 at t0 + h, where the force at t0 is
        // 0.0123; a reviewer's probe, helper-77).
        StepScan scan(m_dyn, step, continuous && m_recorded_before, m_scratch.data());
        m_recorded_before = true;
        double& half = m_half_max[half_index];
        const double floor = period_floor();
        bool new_record = false;
        for (int k = 0; k < active; ++k) {
            const int j = m_active[k];
            ContactMaximum& best = m_max[j];
            const GapEnds ends{m_gap[j], m_rate[j], m_gap_next[j], m_rate_next[j]};
            const PeakAt peak =
                scan.force_peak(j, ends, std::min({best.force, half, floor}), best.impacts);
            if (peak.value > best.force) {
                best.force = peak.value;
                best.time = peak.t;
                new_record = true;
            }
            if (peak.value > half) {
                half = peak.value;
                new_record = true;
            }
            if (peak.value > m_period_max) {
                m_period_max = peak.value;
                new_record = new_record || peak.value > floor;
            }
        }
        if (new_record) set_thresholds(half_index);
    }
    m_gap.swap(m_gap_next);
    m_rate.swap(m_rate_next);
}

void MaxForceTracker::set_thresholds(int half) {
    m_threshold_half = half;
    if (m_dyn.dissipative_contacts()) return;
    // Lowered by a relative 1e-9 so that rounding in the inverse never drops a contact that
    // the exact test of gap_peak() would keep.
    const double floor = period_floor();
    for (std::size_t j = 0; j < m_max.size(); ++j)
        m_threshold[j] = (1.0 - 1e-9) * m_dyn.penetration_at_force(
                                            static_cast<int>(j),
                                            std::min({m_max[j].force, m_half_max[half], floor}));
}

double MaxForceTracker::period_floor() const {
    const bool full = m_top_periods.size() == static_cast<std::size_t>(tail_periods);
    return std::max(m_period_max, full ? m_top_periods.front() : 0.0);
}

void MaxForceTracker::start_period(long n) {
    if (m_period >= 0) {
        const auto smallest_first = std::greater<>();
        if (m_top_periods.size() < static_cast<std::size_t>(tail_periods)) {
            m_top_periods.push_back(m_period_max);
            std::push_heap(m_top_periods.begin(), m_top_periods.end(), smallest_first);
        } else if (m_period_max > m_top_periods.front()) {
            std::pop_heap(m_top_periods.begin(), m_top_periods.end(), smallest_first);
            m_top_periods.back() = m_period_max;
            std::push_heap(m_top_periods.begin(), m_top_periods.end(), smallest_first);
        }
    }
    m_period = n;
    m_period_max = 0.0;
    ++m_periods_recorded;
}

double MaxForceTracker::tail_spread() const {
    // The top quarter of the record, at most tail_periods: a record under 80 periods had no
    // tail estimate, and its one draw from the halves read as little as 1/26 of the spread
    // over starts (Fig 13's row at f_r = 3.2, rkf45, 60 recorded periods; a reviewer's probe,
    // helper-77, found misses of 1.7 to 4.6 times).
    const auto r = static_cast<int>(std::min<long>(tail_periods, m_periods_recorded / 4));
    if (r < min_tail_periods) return 0.0;
    std::vector<double> top = m_top_periods;
    top.push_back(m_period_max);
    std::sort(top.begin(), top.end(), std::greater<>());
    top.resize(static_cast<std::size_t>(r));
    // Excesses over a high threshold of a maximum in the Gumbel domain (an exponential tail)
    // are exponential with the tail's scale beta; their mean over the top r - 1 estimates it
    // without bias, and the maximum of a window has standard deviation beta pi / sqrt(6).
    double excess = 0.0;
    for (int i = 0; i + 1 < r; ++i)
        excess += top[static_cast<std::size_t>(i)] - top.back();
    return std::numbers::pi / std::sqrt(6.0) * excess / (r - 1);
}

double MaxForceTracker::max_force() const {
    double f = 0.0;
    for (const auto& c : m_max)
        f = std::max(f, c.force);
    return f;
}

namespace {

/// The longest lag longer_cycle() tries: 4 max_period, at most 1000, and within the states 32 MB
/// hold (a row of a million bodies keeps max_period + 2 states, 290 MB, and tries none).
int longest_lag(int dimension, int max_period) {
    constexpr double budget_bytes = 32e6;
    const double states = budget_bytes / (8.0 * std::max(dimension, 1));
    const double affordable = std::max(0.0, std::floor(states) - 2.0);
    return std::max(max_period, static_cast<int>(std::min({4.0 * max_period, 1000.0, affordable})));
}

} // namespace

SteadyStateDetector::SteadyStateDetector(int dimension, int max_period, double tolerance,
                                         long earliest_stop, double velocity_scale)
    : m_dim(dimension), m_max_period(max_period), m_tolerance(tolerance),
      m_earliest_stop(earliest_stop), m_velocity_scale(velocity_scale) {
    detail::require_range("run.max_steady_period", max_period, 1, 1000);
    detail::require_range("run.steady_tolerance", tolerance, 0.0, 1.0, detail::Bound::open_low);
    detail::require_range("velocity_scale", velocity_scale, 0.0, 1e12, detail::Bound::open_low);
    m_longest_lag = longest_lag(dimension, max_period);
    m_ring.assign(static_cast<std::size_t>(m_longest_lag) + 2, std::vector<double>(dimension));
}

// The steady-state test tries periods up to max_period only, and a run on a longer cycle read
// "no periodic steady state" (the Nm = 5 row at fc = 10, eps = 0.1, e_r = 0.06, f_r = 1.6 ends
// on period-18 orbits). The test's own tolerance, not far_distance: a torus whose rotation is
// near m / k comes back within 1e-3 after k periods forever (Fig 13's row at f_r = 3.2, k = 47),
// and a raised max_steady_period would not let it settle.
std::optional<int> SteadyStateDetector::longer_cycle() const {
    if (m_period) return std::nullopt;
    for (int k = m_max_period + 1; k <= m_longest_lag; ++k)
        if (matches_period(m_last_boundary, k)) return k;
    return std::nullopt;
}

double SteadyStateDetector::distance(long a, long b) const {
    const auto& ya = m_ring[a % m_ring.size()];
    const auto& yb = m_ring[b % m_ring.size()];
    double scale = 1.0;
    double diff = 0.0;
    for (int i = 0; i < m_dim; ++i) {
        scale = std::max(scale, std::abs(ya[i]));
        diff = std::max(diff, std::abs(ya[i] - yb[i]));
    }
    return diff / scale;
}

bool SteadyStateDetector::matches(long a, long b) const {
    return distance(a, b) <= m_tolerance;
}

bool SteadyStateDetector::matches_period(long n, int k) const {
    return n - 1 - k >= 0 && matches(n, n - k) && matches(n - 1, n - 1 - k);
}

// A cycle approached along a negative multiplier passes the 2k test before the k one (the
// d-distance stays |mu| / (1 - |mu|) times the 2d-distance, |mu| the multiplier per d periods),
// so a period-3 orbit was reported as period 6; one approached along a turning deviation (a
// lightly damped row: eps = 0.01, f_r = 1.3 turns 0.77 of a turn per period) passes the k test
// first for the k whose turns nearly close (period 4). A divisor that nearly matches is watched
// while its distance keeps shrinking; a genuine k-cycle's divisor distance settles at its split
// and ends the watch. The test's distance (the largest component) of a turning deviation swings
// with its direction, sampled once a period with beats of tens of periods near f_r = 2 j / m:
// the watch measures u and v / (natural angular frequency) instead, in which a free vibration
// turns on a circle and its deviation only decays. Each divisor is watched on its own (a
// genuine period-2 orbit detected as 10 has divisor distances 1 and 5 stuck at its split while
// 2's decays), by its largest distance over windows of max(4 k, 64) periods (the distance still
// ripples by some 5 % over tens of periods); a fall of 1 % per window is enough (eps = 0.003 at f_r
// = 2.7 falls 11 %).
bool SteadyStateDetector::shorten_to_divisor(long n) {
    for (int d = 1; d < *m_period; ++d) {
        if (*m_period % d == 0 && matches_period(n, d)) {
            m_period = d;
            return true;
        }
    }
    return false;
}

double SteadyStateDetector::divisor_distance(long n) const {
    double nearest = std::numeric_limits<double>::infinity();
    for (int d = 1; d < *m_period; ++d)
        if (*m_period % d == 0) nearest = std::min(nearest, distance(n, n - d));
    return nearest;
}

void SteadyStateDetector::start_watch(long n) {
    m_watch = {};
    if (divisor_distance(n) > near_divisor_factor * m_tolerance) return;
    for (int d = 1; d < *m_period; ++d)
        if (*m_period % d == 0) {
            m_watch.divisors.push_back(d);
            m_watch.previous_max.push_back(std::numeric_limits<double>::infinity());
            m_watch.window_max.push_back(turn_free_distance(n, n - d));
        }
    m_watch.window_end = n + watch_window();
    m_watch.end = n + std::max(64L * *m_period, 4096L);
}

long SteadyStateDetector::watch_window() const {
    return std::max(4L * *m_period, 64L);
}

double SteadyStateDetector::turn_free_distance(long a, long b) const {
    const auto& ya = m_ring[a % m_ring.size()];
    const auto& yb = m_ring[b % m_ring.size()];
    const int half = m_dim / 2;
    double sum = 0.0;
    for (int i = 0; i < m_dim; ++i) {
        const double d = (ya[i] - yb[i]) / (i < half ? 1.0 : m_velocity_scale);
        sum += d * d;
    }
    return std::sqrt(sum);
}

void SteadyStateDetector::watch_divisors(long n) {
    // A period shortened to d may itself be a multiple of the true one (8 -> 2 -> 1 for a
    // deviation turning 0.37 of a turn per period): its divisors are watched in turn.
    if (shorten_to_divisor(n)) {
        start_watch(n);
        return;
    }
    if (n >= m_watch.end) {
        m_watch = {};
        return;
    }
    DivisorWatch& w = m_watch;
    for (std::size_t i = 0; i < w.divisors.size(); ++i)
        w.window_max[i] = std::max(w.window_max[i], turn_free_distance(n, n - w.divisors[i]));
    if (n < w.window_end) return;
    bool shrinking = false;
    for (std::size_t i = 0; i < w.divisors.size(); ++i)
        shrinking = shrinking || w.window_max[i] <= 0.99 * w.previous_max[i];
    if (!shrinking) {
        m_watch = {};
        return;
    }
    w.previous_max = w.window_max;
    std::fill(w.window_max.begin(), w.window_max.end(), 0.0);
    w.window_end = n + watch_window();
}

bool SteadyStateDetector::on_period(long n, double t, const double* y) {
    std::copy(y, y + m_dim, m_ring[n % m_ring.size()].begin());
    m_last_boundary = n;
    if (m_period) {
        if (m_watch.end >= 0) watch_divisors(n);
        return m_watch.end < 0 && n >= m_earliest_stop + *m_period;
    }
    if (n > m_max_period) {
        m_nearest = std::numeric_limits<double>::infinity();
        for (int k = 1; k <= m_max_period; ++k)
            m_nearest = std::min(m_nearest, distance(n, n - k));
        if (m_nearest > far_distance) m_last_far = n;
    }
    for (int k = 1; k <= m_max_period; ++k) {
        if (n - 1 - k < 0) break;
        if (matches_period(n, k)) {
            m_period = k;
            m_time = t;
            start_watch(n);
            break;
        }
    }
    return m_period.has_value() && m_watch.end < 0 && n >= m_earliest_stop + *m_period;
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
