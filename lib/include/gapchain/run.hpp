#pragma once
/// \file run.hpp
/// The time loop, written once. It advances a state period by period on a StepPlan and streams
/// every step to observers; observers may ask it to stop at a period boundary.

#include "gapchain/dynamics.hpp"
#include "gapchain/stepper.hpp"

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace gapchain {

/// One step as the observers see it: both ends, so that they can interpolate in between.
struct StepView {
    double t0;                        ///< reduced time at the start of the step
    double t1;                        ///< reduced time at the end of the step
    const double* y0;                 ///< state at t0 (2 Nm entries)
    const double* y1;                 ///< state at t1
    long period;                      ///< index of the forcing period the step lies in, from 0
    bool recording;                   ///< false while the transient is being discarded
    const Stepper* stepper = nullptr; ///< the stepper, for its dense output over this step
};

/// Receives the run step by step. Observers are single-threaded; one instance per run.
class Observer {
public:
    virtual ~Observer() = default;
    /// Called once per step, in time order.
    virtual void on_step(const StepView& step) = 0;
    /// Called at t = t_start (n = 0) and at the end of every forcing period n >= 1, with the
    /// state there. Return true to ask the loop to stop (it stops if the periods requested
    /// so far allow).
    virtual bool on_period(long n, double t, const double* y) {
        (void)n, (void)t, (void)y;
        return false;
    }
    /// The work of one on_step against that of a step of the row itself (>= 0; 0: negligible),
    /// so that a run asks its progress callback as often in time whatever observes it (a
    /// tangent flow of k vectors costs about k steps).
    [[nodiscard]] virtual double step_cost() const { return 0.0; }
};

/// How long a run lasts, in forcing periods.
struct RunSpan {
    long periods = 1000;        ///< total periods, >= 1
    long transient_periods = 0; ///< first periods not recorded, 0 <= transient < periods
    double t_start = 0.0;       ///< reduced time of the initial state (forcing phase 2 pi f_r t)
    /// Index of the period the initial state starts, 0 .. periods - 1: a run in phases
    /// continues the period count (and the observers' state) of the phase before it. Periods
    /// first_period .. periods - 1 are integrated; on_period(0) is called only when it is 0.
    long first_period = 0;
};

/// How a run ended.
enum class RunStatus {
    completed,    ///< all requested periods were integrated
    steady_state, ///< an observer found a periodic steady state and the run stopped early
    non_finite,   ///< the state became NaN or infinite (message names time and body)
    cancelled,    ///< the progress callback asked to stop
};

/// Name of a status, as written in results ("completed", "steady_state", ...).
std::string_view to_string(RunStatus status);

/// What the loop did.
struct RunOutcome {
    RunStatus status = RunStatus::completed; ///< how the run ended (a numerical outcome)
    long periods_done = 0;                   ///< forcing periods integrated
    long steps = 0;                          ///< steps taken
    double t_end = 0.0;                      ///< reduced time at the end
    Scheme scheme = Scheme::rk4;             ///< the concrete scheme the run took
    /// Its step in reduced time (an adaptive scheme's output interval); 0: the run never
    /// started.
    double step = 0.0;
    std::string message; ///< why a run failed (empty otherwise)
};

/// Progress report: fraction done in [0, 1]; return false to cancel the run.
using ProgressCallback = std::function<bool(double fraction_done)>;

/// RunOptions::transient_periods value asking for MODEL.md §2's default transient.
inline constexpr long auto_transient = -1;

/// How strictly a run is held to its tolerance.
enum class AccuracyMode {
    /// "auto": a run that shows it does not settle (no steady state, far from every cycle and
    /// not approaching one, once the transient is over) may finish on a cheaper plan whose F_m
    /// error stays well below its sampling spread (see simulate()). Periodic runs are held to
    /// the tolerance.
    automatic,
    strict, ///< "strict": every step held to run.tolerance pointwise
};

/// Parses "auto" or "strict"; throws std::invalid_argument naming run.accuracy_mode otherwise.
AccuracyMode parse_accuracy_mode(std::string_view name);
/// The scene name of a mode.
std::string_view to_string(AccuracyMode mode);

/// How to run: length, scheme, accuracy, steady-state stop. Defaults are MODEL.md §2's (1000
/// periods, the start-up transient discarded).
struct RunOptions {
    long periods = 1000; ///< forcing periods, 1 .. 1e9
    /// Discarded first periods, 0 .. periods - 1, or auto_transient (default_transient_periods).
    long transient_periods = auto_transient;
    Scheme scheme = Scheme::automatic; ///< integration scheme
    double tolerance = 1e-4;           ///< relative accuracy asked of F_m, 1e-12 .. 0.1
    std::optional<double> step;        ///< user step (reduced time), overrides the tolerance
    bool stop_at_steady_state = true;  ///< stop once the state at the period repeats
    double steady_tolerance = 1e-10;   ///< relative repeat tolerance, (0, 1)
    int max_steady_period = 16;        ///< largest steady period tried, 1 .. 1000
    bool estimate_error = true;        ///< estimate F_m_error (simulate(): comparison run or
                                       ///< window halves)
    /// simulate(): when the run settled late or never, run a twin from a start moved by 1e-8
    /// and flag the answer multistable if its F_m differs beyond the error estimate.
    bool multistability_check = true;
    /// Whether a run that never settles may finish on a cheaper plan (AccuracyMode).
    AccuracyMode accuracy_mode = AccuracyMode::automatic;
    /// Largest work a run may take, in body-steps (Nm x steps per period x periods), 1 ..
    /// 1e15. About 1e7 body-steps run per second on one core, so the default 3e10 is about an
    /// hour; a larger run is refused up front with its estimate.
    double max_work = 3e10;
};

/// Throws std::invalid_argument naming the first option outside its range.
void validate(const RunOptions& options);

/// MODEL.md §2's default transient [forcing periods]: the time in which the slowest free
/// vibration of the contact-free row decays below options.tolerance,
/// n_t = max(1, ceil(f_r ln(1 / tol) / r_min)) with r_min the slowest body's decay rate:
/// c_i / 2 for an underdamped body (c_i = damping_i; 2 pi eps for the paper's row, eps < 1),
/// c_i / 2 - sqrt(c_i^2 / 4 - k_i) for an overdamped one (k_i = spring_i: its slow root, 4 pi^2
/// / (2 pi (eps + sqrt(eps^2 - 1))) for the paper's row, 0.0314 at eps = 100 where 2 pi eps
/// is 628), capped at options.periods / 2 (the cap when r_min = 0); 0 for a record (no
/// forcing period: the start is part of the motion).
long default_transient_periods(const Dynamics& dyn, const RunOptions& options);

/// default_transient_periods() without its cap: the forcing periods in which the contact-free
/// row's start-up decays to `tolerance` (in (0, 1)), at most 1e9 (also where nothing decays,
/// eps = 0); 0 for a record.
long start_up_decay_periods(const Dynamics& dyn, double tolerance);

/// options with transient_periods resolved: auto_transient replaced by
/// default_transient_periods(), any other value kept.
RunOptions with_transient_resolved(const Dynamics& dyn, RunOptions options);

/// Integrates y (2 Nm entries, updated in place) over span on plan's step grid, feeding every
/// observer. Throws std::invalid_argument on an inconsistent span or state size.
RunOutcome run(const Dynamics& dyn, Stepper& stepper, const StepPlan& plan, const RunSpan& span,
               std::vector<double>& y, std::span<Observer* const> observers,
               const ProgressCallback& progress = {});

/// The step plan of options (plan_step on its scheme, tolerance and step); with
/// samples_per_period >= 1, refined so that it divides the steps per period (samples then fall
/// on step ends). 0: no refinement.
StepPlan plan_run(const Dynamics& dyn, const RunOptions& options, int samples_per_period = 0);

/// plan on a finer grid, for a comparison run that measures plan's error: twice the steps of a
/// fixed-step scheme (the exact propagator's output interval); an adaptive scheme's tolerance
/// divided by tolerance_divisor (> 1; at least 1e-12) and its output interval halved.
StepPlan finer_plan(const Dynamics& dyn, const StepPlan& plan, double tolerance_divisor);

/// The contact switches one forcing period is counted to hold, for work and size estimates:
/// two per contact per natural period (reduced time 1), 2 (Nm + 1) x the forcing period. Each
/// splits a step into one more piece (a trajectory row, an RK4 step or a propagator product).
double contact_switches_per_period(const Dynamics& dyn);

/// Work of a run of `periods` forcing periods of dyn on plan, in body-steps (about 1e7 a
/// second), carrying `tangents` tangent vectors (0 .. 2 Nm) along: Nm x steps per period for
/// every vector; on the exact propagator a step is a dense (2 Nm)^2 product per vector, each
/// contact switch (contact_switches_per_period()) about 100 more and a product per vector, a
/// critically damped body a matrix exponential (2 Nm)^3 / 20 per switch, and
/// every contact closing and opening once a period may call for a new configuration's
/// eigendecomposition, (2 Nm)^3, up to the 2^(Nm + 1) configurations a short row has (its
/// cache keeps them all up to Nm = 11). An upper estimate where a row repeats configurations.
double run_work(const Dynamics& dyn, const StepPlan& plan, double periods, int tangents = 0);

/// The whole forcing periods of dyn on plan that run_work() fits into max_work (>= 0).
double affordable_periods(const Dynamics& dyn, const StepPlan& plan, double max_work);

/// The check every run makes before it starts, callable without running: throws
/// std::invalid_argument naming run.max_work, with the estimated work (period_work() x
/// periods, in body-steps) and how long it would take, when the run of options on dyn
/// exceeds options.max_work. Also throws on invalid options (validate()).
void require_affordable(const Dynamics& dyn, const RunOptions& options);

/// As require_affordable(), for a run of options' periods on `plan` (another run's step, as an
/// error estimate's comparison): the message says `what` ("... takes up to") and puts `remedy`
/// ("..., " or empty) first among the ways out.
void require_affordable(const Dynamics& dyn, const RunOptions& options, const StepPlan& plan,
                        const std::string& what, const std::string& remedy);

/// One run set up from options, the set-up every analysis shares: options validated, the step
/// planned, the stepper made, the initial state checked. The caller runs it with the observers
/// it needs. dyn must outlive it.
class PlannedRun {
public:
    /// initial: 2 Nm entries, or empty for rest; samples_per_period as in plan_run().
    PlannedRun(const Dynamics& dyn, const RunOptions& options,
               const std::vector<double>& initial = {}, int samples_per_period = 0);
    /// The same options on a given plan (a comparison run at another step).
    PlannedRun(const Dynamics& dyn, const RunOptions& options, const StepPlan& plan,
               const std::vector<double>& initial);
    /// Runs options.periods from t = 0, options.transient_periods not recorded, from the
    /// current state (updated in place).
    RunOutcome run(std::span<Observer* const> observers, const ProgressCallback& progress = {});
    /// Runs another span from the current state (a run in phases).
    RunOutcome run(const RunSpan& span, std::span<Observer* const> observers,
                   const ProgressCallback& progress = {});
    /// The plan the run uses.
    [[nodiscard]] const StepPlan& plan() const { return m_plan; }
    /// Periods run() discards first: options.transient_periods, resolved if auto.
    [[nodiscard]] long transient_periods() const { return m_span.transient_periods; }
    /// The current state: the initial state, then the end state of the last run.
    [[nodiscard]] const std::vector<double>& state() const { return m_state; }
    /// Right-hand-side evaluations of the stepper so far.
    [[nodiscard]] long evaluations() const { return m_stepper->evaluations(); }

private:
    const Dynamics& m_dyn;
    RunSpan m_span;
    StepPlan m_plan;
    std::unique_ptr<Stepper> m_stepper;
    std::vector<double> m_state;
};

} // namespace gapchain
