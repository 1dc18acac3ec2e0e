#pragma once
/// \file run.hpp
/// The time loop, written once. It advances a state period by period on a StepPlan and streams
/// every step to observers; observers may ask it to stop at a period boundary.

#include "gapchain/dynamics.hpp"
#include "gapchain/stepper.hpp"

#include <functional>
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
};

/// How long a run lasts, in forcing periods.
struct RunSpan {
    long periods = 1000;        ///< total periods, >= 1
    long transient_periods = 0; ///< first periods not recorded, 0 <= transient < periods
    double t_start = 0.0;       ///< reduced time of the initial state (forcing phase 2 pi f_r t)
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
    RunStatus status = RunStatus::completed;
    long periods_done = 0; ///< forcing periods integrated
    long steps = 0;        ///< steps taken
    double t_end = 0.0;    ///< reduced time at the end
    std::string message;   ///< why a run failed (empty otherwise)
};

/// Progress report: fraction done in [0, 1]; return false to cancel the run.
using ProgressCallback = std::function<bool(double fraction_done)>;

/// Integrates y (2 Nm entries, updated in place) over span on plan's step grid, feeding every
/// observer. Throws std::invalid_argument on an inconsistent span or state size.
RunOutcome run(const Dynamics& dyn, Stepper& stepper, const StepPlan& plan, const RunSpan& span,
               std::vector<double>& y, std::span<Observer* const> observers,
               const ProgressCallback& progress = {});

} // namespace gapchain
