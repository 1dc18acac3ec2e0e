#include "gapchain/simulation.hpp"

#include "detail/check.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace gapchain {

std::string_view to_string(ErrorMethod method) {
    switch (method) {
    case ErrorMethod::none: return "none";
    case ErrorMethod::comparison_run: return "comparison_run";
    case ErrorMethod::window_halves: return "window_halves";
    }
    return "?";
}

namespace {

struct SingleRun {
    RunOutcome outcome;
    std::vector<ContactMaximum> contacts;
    double F_m = 0.0;
    std::optional<int> period;
    std::optional<double> period_time;
    long evaluations = 0;
    double first_half_max = 0.0;  // largest force in the first half of the recorded window
    double second_half_max = 0.0; // and in the second half
    long last_far_period = -1;    // see SteadyStateDetector::last_far_period()
};

SingleRun run_once(const Dynamics& dyn, const RunOptions& options, PlannedRun& planned,
                   const TrajectorySink& trajectory, int every, const ProgressCallback& progress,
                   const std::vector<Observer*>& extra = {}) {
    MaxForceTracker forces(dyn, options.transient_periods +
                                    (options.periods - options.transient_periods) / 2);
    std::vector<Observer*> observers{&forces};
    std::optional<SteadyStateDetector> steady;
    // A record has no period, so no periodic steady state: it runs to its end.
    if (options.stop_at_steady_state && dyn.ground_motion().is_harmonic()) {
        steady.emplace(dyn.dimension(), options.max_steady_period, options.steady_tolerance,
                       options.transient_periods);
        observers.push_back(&*steady);
    }
    std::optional<TrajectoryRecorder> recorder;
    if (trajectory) {
        recorder.emplace(every, trajectory);
        observers.push_back(&*recorder);
    }
    observers.insert(observers.end(), extra.begin(), extra.end());
    SingleRun r;
    r.outcome = planned.run(observers, progress);
    r.contacts = forces.contacts();
    r.F_m = forces.max_force();
    if (steady) {
        r.period = steady->period();
        r.period_time = steady->time();
        r.last_far_period = steady->last_far_period();
    }
    r.evaluations = planned.evaluations();
    r.first_half_max = forces.first_half_max();
    r.second_half_max = forces.second_half_max();
    return r;
}

/// The main run's maxima, per contact and per body, and where F_m occurred.
void report_maxima(const SingleRun& main, SimulationResult& result) {
    const int n = static_cast<int>(main.contacts.size()) - 1;
    result.per_contact = main.contacts;
    result.per_body.resize(n);
    for (int i = 0; i < n; ++i) {
        result.per_body[i] = {main.contacts[i].force, main.contacts[i + 1].force,
                              main.contacts[i].time, main.contacts[i + 1].time};
    }
    for (int j = 0; j <= n; ++j) {
        const auto& c = main.contacts[j];
        if (c.impacts > 0 || c.force > 0.0) result.contact = true;
        if (c.force > result.F_m) {
            result.F_m = c.force;
            result.F_m_contact = j;
            result.F_m_time = c.time;
        }
    }
}

/// The comparison run's plan. Fixed-step schemes: twice the step (or half, if twice would
/// break the stability limit). GSL adaptive schemes: ten times the tolerance. Exact: half the
/// output interval (its F_m then moves only by round-off and event location).
StepPlan comparison_plan(const Dynamics& dyn, const StepPlan& plan) {
    StepPlan other = plan;
    const SchemeTraits tr = traits(plan.scheme);
    if (plan.scheme == Scheme::rkf45 || plan.scheme == Scheme::rk8pd) {
        other.tolerance = std::min(0.1, 10.0 * plan.tolerance);
    } else if (plan.scheme == Scheme::exact) {
        other.steps_per_period = plan.steps_per_period * 2;
    } else if (plan.steps_per_period >= 2 &&
               2.0 * plan.step * dyn.max_angular_frequency() < 0.9 * tr.stability_limit) {
        other.steps_per_period = plan.steps_per_period / 2;
    } else {
        other.steps_per_period = plan.steps_per_period * 2;
    }
    other.step = dyn.period() / other.steps_per_period;
    return other;
}

/// F_m_error from a comparison run on another plan.
double comparison_error(const Dynamics& dyn, const RunOptions& options, const StepPlan& plan,
                        const std::vector<double>& initial, SimulationResult& result) {
    const StepPlan other = comparison_plan(dyn, plan);
    PlannedRun planned(dyn, options, other, initial);
    const SingleRun check = run_once(dyn, options, planned, {}, 1, {});
    result.evaluations += check.evaluations;
    if (check.outcome.status == RunStatus::non_finite)
        return std::numeric_limits<double>::infinity();
    // Periodic runs converge at the scheme's order p, so the error of F_m is about
    // |F_m - F_m'| / (2^p - 1); we report twice that. Runs that never settle (chaotic, long
    // transients) get the raw difference: there it is not a truncation error.
    const SchemeTraits tr = traits(plan.scheme);
    const double diff = std::abs(result.F_m - check.F_m);
    const double gain = std::ldexp(1.0, tr.order) - 1.0;
    const bool periodic = result.steady_state_period && check.period && !tr.adaptive &&
                          other.steps_per_period < plan.steps_per_period;
    // A finer comparison run (stability fallback) differs by (1 - 2^-p) of the error.
    const bool finer = !tr.adaptive && other.steps_per_period > plan.steps_per_period;
    const double estimate = periodic ? 2.0 * diff / gain : (finer ? 2.0 * diff : diff);
    // Round-off floor: F_m is never known better than a few ulps of itself; for exact, whose
    // two runs share the same eigendecompositions and so the same round-off, the floor is what
    // it measured against rk8pd at 1e-10 (6e-13 relative, accuracy.md).
    const double floor = plan.scheme == Scheme::exact ? 1e-12 : 1e-14;
    return std::max(estimate, floor * result.F_m);
}

/// F_m_error and how it was estimated.
void estimate_error(const Dynamics& dyn, const RunOptions& options, const StepPlan& plan,
                    const std::vector<double>& initial, const SingleRun& main,
                    SimulationResult& result) {
    if (!options.estimate_error) return;
    // A harmonic run that never settled (chaotic, quasi-periodic, or a steady period above
    // max_steady_period) has an F_m that depends on the window: the maxima of the two halves
    // of the recorded window differ by a sampling spread that, when it is well above the
    // scheme's truncation error (~ tolerance * F_m), is the error to report; the comparison
    // run would only measure the same spread again, at the cost of a second full-length run.
    const double half_spread = std::abs(main.first_half_max - main.second_half_max);
    const bool sampling_dominated = result.status == RunStatus::completed &&
                                    dyn.ground_motion().is_harmonic() &&
                                    options.periods - options.transient_periods >= 2 &&
                                    half_spread > 10.0 * options.tolerance * result.F_m;
    if (sampling_dominated) {
        result.F_m_error = half_spread;
        result.error_method = ErrorMethod::window_halves;
    } else if (result.status != RunStatus::non_finite && result.status != RunStatus::cancelled) {
        result.error_method = ErrorMethod::comparison_run;
        result.F_m_error = comparison_error(dyn, options, plan, initial, result);
    }
}

/// Whether a run needs the twin check: it never settled, or it stayed far from every cycle
/// (SteadyStateDetector::far_distance) for more than four times the contact-free row's decay
/// time to that distance. A start-up that decays onto a stable orbit is far for about one such
/// time (two to four near bifurcations, where the orbit attracts slowly; measured on Fig 13's
/// line); a chaotic transient that wanders before it is captured, for many.
bool settled_late(const Dynamics& dyn, const RunOptions& options, const SingleRun& main) {
    if (!options.stop_at_steady_state) return false;
    if (main.outcome.status == RunStatus::completed) return true;
    if (main.outcome.status != RunStatus::steady_state || main.last_far_period < 0) return false;
    RunOptions free_decay = options;
    free_decay.tolerance = SteadyStateDetector::far_distance;
    return main.last_far_period > 4 * default_transient_periods(dyn, free_decay);
}

/// The twin run of the multistability check (see simulate()).
void check_multistability(const Dynamics& dyn, const RunOptions& options,
                          const std::vector<double>& initial, const SingleRun& main,
                          SimulationResult& result) {
    if (!options.multistability_check || !dyn.ground_motion().is_harmonic() ||
        !settled_late(dyn, options, main))
        return;
    std::vector<double> start =
        initial.empty() ? std::vector<double>(dyn.dimension(), 0.0) : initial;
    double scale = 1.0;
    for (double x : start)
        scale = std::max(scale, std::abs(x));
    start[0] += 1e-8 * scale;
    PlannedRun planned(dyn, options, start);
    const SingleRun twin = run_once(dyn, options, planned, {}, 1, {});
    result.evaluations += twin.evaluations;
    if (twin.outcome.status == RunStatus::non_finite || twin.outcome.status == RunStatus::cancelled)
        return;
    result.twin_checked = true;
    result.F_m_twin = twin.F_m;
    // Each run's own sampling spread (its window halves), whether or not F_m_error was asked.
    const auto spread = [](const SingleRun& r) {
        return r.outcome.status == RunStatus::completed
                   ? std::abs(r.first_half_max - r.second_half_max)
                   : 0.0;
    };
    const double difference = std::abs(twin.F_m - result.F_m);
    const double allowed = std::max(
        {3.0 * result.F_m_error, 3.0 * spread(main), 3.0 * spread(twin), 1e-6 * result.F_m});
    if (difference > allowed) {
        result.multistable = true;
        result.F_m_error = std::max(result.F_m_error, difference);
    }
}

} // namespace

SimulationResult simulate(const Dynamics& dyn, const RunOptions& requested,
                          const std::vector<double>& initial, const SimulationHooks& hooks) {
    const auto start = std::chrono::steady_clock::now();
    validate(requested);
    const RunOptions options = with_transient_resolved(dyn, requested);
    PlannedRun planned(dyn, options, initial);
    const SingleRun main =
        run_once(dyn, options, planned, hooks.trajectory, std::max(1, hooks.trajectory_every),
                 hooks.progress, hooks.observers);
    SimulationResult result;
    result.status = main.outcome.status;
    result.message = main.outcome.message;
    result.scheme = planned.plan().scheme;
    result.step = planned.plan().step;
    result.periods_simulated = main.outcome.periods_done;
    result.transient_periods_used = options.transient_periods;
    result.steps = main.outcome.steps;
    result.evaluations = main.evaluations;
    result.steady_state_period = main.period;
    result.steady_state_time = main.period_time;
    result.final_state = planned.state();
    report_maxima(main, result);
    estimate_error(dyn, options, planned.plan(), initial, main, result);
    if (result.status == RunStatus::completed || result.status == RunStatus::steady_state)
        check_multistability(dyn, options, initial, main, result);
    result.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

} // namespace gapchain
