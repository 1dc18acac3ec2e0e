#pragma once
/// \file observers.hpp
/// Observers of the time loop. A run switches on only the ones its scene needs.

#include "gapchain/dynamics.hpp"
#include "gapchain/run.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

namespace gapchain {

/// The largest force one contact reached while recording, and its impacts.
struct ContactMaximum {
    double force = 0.0; ///< reduced force max_t F_j(t), >= 0 (0: never closed)
    double time = 0.0;  ///< reduced time of that maximum
    long impacts = 0;   ///< times the contact closed while recording (a run stopped at its
                        ///< steady state counts up to the stop, not the requested periods)
};

/// Tracks max_t F_j(t) for every contact j. Peaks between steps are located on the quintic
/// Hermite interpolant of the gap (value, rate and acceleration at both ends), so F_m carries
/// no O(h^2) step-point bias. O(Nm) memory and O(Nm) work per step.
class MaxForceTracker final : public Observer {
public:
    /// dyn must outlive the tracker. split_period: the recorded window is also split in two
    /// at this forcing period (steps of periods < split_period form the first half), and the
    /// largest force of each half is kept; -1 (default): no split.
    explicit MaxForceTracker(const Dynamics& dyn, long split_period = -1);
    void on_step(const StepView& step) override;
    /// Per contact j = 0..Nm (0: left wall, Nm: right wall).
    [[nodiscard]] const std::vector<ContactMaximum>& contacts() const { return m_max; }
    /// F_m: the largest force over all contacts while recording (eq 19), >= 0.
    [[nodiscard]] double max_force() const;
    /// Largest force over all contacts in the recorded periods before split_period, >= 0.
    [[nodiscard]] double first_half_max() const { return m_half_max[0]; }
    /// Largest force over all contacts in the recorded periods from split_period on, >= 0.
    [[nodiscard]] double second_half_max() const { return m_half_max[1]; }
    /// |first_half_max() - second_half_max()|: the sampling spread of the maximum over a window
    /// that does not repeat; 0 without a split.
    [[nodiscard]] double half_spread() const {
        return m_split_period >= 0 ? std::abs(m_half_max[0] - m_half_max[1]) : 0.0;
    }
    /// The standard deviation of the window's maximum over windows like it, from the tail of
    /// its per-period maxima: pi / sqrt(6) (a Gumbel maximum's) times their mean excess over
    /// the r-th largest, the exponential tail's scale, r the top quarter of the recorded
    /// periods and at most tail_periods. 0 with fewer than 4 min_tail_periods recorded
    /// periods. Meaningful for a window that does not repeat (a periodic one's per-period
    /// maxima take k values, and its maximum is known).
    [[nodiscard]] double tail_spread() const;
    /// Per-period maxima whose tail tail_spread() reads at most: its relative error is about
    /// 1 / sqrt(r - 1), 23 % from 80 recorded periods on.
    static constexpr int tail_periods = 20;
    /// The fewest it reads: 6 (relative error about 45 %), from 24 recorded periods on.
    static constexpr int min_tail_periods = 6;
    /// The error of max_force() as a window's answer: half_spread(), at least tolerance
    /// (relative, the run's accuracy, in (0, 1)) times max_force(); with repeats = false (the
    /// window did not repeat) at least tail_spread() too.
    [[nodiscard]] double window_error(double tolerance, bool repeats) const {
        return std::max({half_spread(), tolerance * max_force(), repeats ? 0.0 : tail_spread()});
    }

private:
    const Dynamics& m_dyn;
    std::vector<ContactMaximum> m_max;
    std::vector<double> m_gap;                   ///< g_j at the end of the previous step
    std::vector<double> m_rate;                  ///< dg_j/dt there
    std::vector<double> m_gap_next, m_rate_next; ///< the same at the end of this step
    std::vector<int> m_active;                   ///< contacts this step has to scan
    std::vector<double> m_flag; ///< per contact: 1 to scan, + 2 when it closed in this step
    /// Per contact, the penetration below which no peak can beat its record (its own maximum
    /// or the current half's, whichever is lower); 0 for Hunt-Crossley, whose force also
    /// grows with the closing rate.
    std::vector<double> m_threshold;
    int m_threshold_half = -1;     ///< the window half the thresholds were set for
    std::vector<double> m_scratch; ///< a state from the stepper's dense output
    double m_last_t = -1.0;
    bool m_have_previous = false;
    bool m_recorded_before = false; // a step was recorded: the next one's start is counted
    long m_split_period;
    double m_half_max[2] = {0.0, 0.0};
    /// The tail_periods largest maxima of the recorded periods before m_period (a min-heap:
    /// the smallest first), the maximum of period m_period so far, and the periods recorded.
    std::vector<double> m_top_periods;
    long m_period = -1;
    double m_period_max = 0.0;
    long m_periods_recorded = 0;

    /// The force below which a peak changes nothing of the per-period tail: the current
    /// period's maximum, or the smallest kept maximum once tail_periods are kept.
    [[nodiscard]] double period_floor() const;
    /// Starts recording period n: the last one's maximum joins the kept ones if it is large.
    void start_period(long n);

    /// Sets m_threshold from the records, for window half `half` (0 or 1).
    void set_thresholds(int half);
    /// Counts the closings of a recorded step of length h and lists in m_active the contacts
    /// that could beat their records in it; returns how many.
    int list_contacts_to_scan(double h);
};

/// Detects a periodic steady state from the states at the forcing-period boundaries: the run
/// is periodic with period k (in forcing periods) when the boundary states k periods apart
/// agree to tolerance * (1 + |y|_inf) at two consecutive boundaries. O(k_max Nm) memory.
class SteadyStateDetector final : public Observer {
public:
    /// dimension: state size 2 Nm; max_period: largest k tried (>= 1); tolerance > 0;
    /// earliest_stop: first recorded period; a stop is asked for only once a whole steady
    /// period k has been recorded after it (so the recorded maxima cover the orbit);
    /// velocity_scale > 0: the divisor watch measures u and v / velocity_scale (a body's natural
    /// angular frequency, 2 pi in reduced units, keeps the size of a free vibration's deviation
    /// as it turns).
    SteadyStateDetector(int dimension, int max_period, double tolerance, long earliest_stop,
                        double velocity_scale = 1.0);
    void on_step(const StepView&) override {}
    bool on_period(long n, double t, const double* y) override;
    /// Period k of the steady state, once found: the smallest k whose test passed, shortened to
    /// a divisor d of k that passes later, when the divisors' distance was already within
    /// near_divisor_factor * tolerance and one of them keeps shrinking: its largest value (u, v
    /// / velocity_scale, 2-norm) over consecutive windows of max(4 k, 64) periods falls by 1 %
    /// or more (the stop waits for that: at most max(64 k, 4096) periods). A shortened period's
    /// own divisors are watched in turn. A deviation that decays by less than 1 % in 64 periods
    /// (eps below about 0.0003 at f_r = 2.7) may keep a multiple of the true period.
    [[nodiscard]] std::optional<int> period() const { return m_period; }
    /// Reduced time at which it was found.
    [[nodiscard]] std::optional<double> time() const { return m_time; }
    /// The last period n whose state was farther than far_distance (relative) from every one of
    /// the max_period states before it: when the run was last far from any cycle it could be
    /// on. -1 if none.
    [[nodiscard]] long last_far_period() const { return m_last_far; }
    /// How close (in tolerances) a divisor of a detected period must be to get its extra periods.
    static constexpr double near_divisor_factor = 1e4;
    /// The relative distance last_far_period() uses.
    static constexpr double far_distance = 1e-3;
    /// Where no steady state was found: the shortest lag k beyond max_period (up to 4 max_period
    /// and 1000, and as many states as 32 MB hold; none on rows too large for one more) at which
    /// the last two boundaries pass the steady-state test: the run ended on a cycle of k periods,
    /// on which a test trying k periods stops. Empty otherwise.
    [[nodiscard]] std::optional<int> longer_cycle() const;
    /// At the last period boundary n > max_period: the relative distance from the state there
    /// to the nearest of the max_period states before it (how close the run is to a cycle);
    /// +inf before.
    [[nodiscard]] double nearest_cycle_distance() const { return m_nearest; }

private:
    /// max |y_a - y_b| / max(1, max |y_a|) over the state.
    [[nodiscard]] double distance(long a, long b) const;
    [[nodiscard]] bool matches(long a, long b) const;
    /// Boundaries n and n - 1 both match k periods back.
    [[nodiscard]] bool matches_period(long n, int k) const;
    /// Shortens m_period to its smallest divisor that matches at n; true if it did.
    bool shorten_to_divisor(long n);
    /// Smallest distance from boundary n to a proper divisor of m_period back (+inf if none).
    [[nodiscard]] double divisor_distance(long n) const;
    /// Watches m_period's divisors from boundary n if one is within near_divisor_factor.
    void start_watch(long n);
    /// Periods over which the watch takes the largest divisor distance: max(4 k, 64).
    [[nodiscard]] long watch_window() const;
    /// |y_a - y_b| in the watch's norm: 2-norm of u and v / velocity_scale.
    [[nodiscard]] double turn_free_distance(long a, long b) const;
    /// One boundary of the watch on a nearly matching divisor (see period()).
    void watch_divisors(long n);
    int m_dim;
    int m_max_period;
    double m_tolerance;
    long m_earliest_stop;
    /// The longest lag longer_cycle() tries (max_period: none).
    int m_longest_lag;
    /// Boundary states, n modulo m_longest_lag + 2.
    std::vector<std::vector<double>> m_ring;
    long m_last_boundary = -1; ///< the last boundary n seen
    std::optional<int> m_period;
    std::optional<double> m_time;
    long m_last_far = -1;
    double m_velocity_scale;
    /// The divisors being watched, each with its largest turn_free_distance() over the last
    /// whole window and over the current one; the current window's last boundary and the
    /// watch's (end < 0: none).
    struct DivisorWatch {
        std::vector<int> divisors;
        std::vector<double> previous_max;
        std::vector<double> window_max;
        long window_end = -1;
        long end = -1;
    } m_watch;
    double m_nearest = std::numeric_limits<double>::infinity();
};

/// Receives (t, y) samples of a recorded trajectory: t in reduced time, y the 2 Nm state (u
/// then v, reduced, relative to the ground).
using TrajectorySink = std::function<void(double t, const double* y)>;

/// Streams every `every`-th step's end state (while recording) to a sink; stores nothing.
class TrajectoryRecorder final : public Observer {
public:
    /// every >= 1: decimation factor in steps.
    TrajectoryRecorder(int every, TrajectorySink sink);
    void on_step(const StepView& step) override;

private:
    int m_every;
    long m_count = 0;
    TrajectorySink m_sink;
};

} // namespace gapchain
