#pragma once
/// \file simulation.hpp
/// One simulation of a row: F_m (eq 19) with its error estimate, per-contact and per-body
/// maxima, impact counts, the periodic steady state if any, and the run time.

#include "gapchain/dynamics.hpp"
#include "gapchain/observers.hpp"
#include "gapchain/run.hpp"
#include "gapchain/stepper.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gapchain {

/// How to run one simulation. Defaults are the paper's (1000 periods, transient counted).
struct RunOptions {
    long periods = 1000;               ///< forcing periods, 1 .. 1e9
    long transient_periods = 0;        ///< discarded first periods, 0 .. periods - 1
    Scheme scheme = Scheme::automatic; ///< integration scheme
    double tolerance = 1e-4;           ///< relative accuracy asked of F_m, 1e-12 .. 0.1
    std::optional<double> step;        ///< user step (reduced time), overrides the tolerance
    bool stop_at_steady_state = true;  ///< stop once the state at the period repeats
    double steady_tolerance = 1e-10;   ///< relative repeat tolerance, (0, 1)
    int max_steady_period = 16;        ///< largest steady period tried, 1 .. 1000
    bool estimate_error = true;        ///< second run at twice the step for F_m_error
};

/// Throws std::invalid_argument naming the first option outside its range.
void validate(const RunOptions& options);

/// The larger of the left and right contact forces one body felt.
struct BodyMaximum {
    double left = 0.0;    ///< max reduced force from the contact on its left
    double right = 0.0;   ///< max reduced force from the contact on its right
    double t_left = 0.0;  ///< reduced time of the left maximum
    double t_right = 0.0; ///< reduced time of the right maximum
};

/// How SimulationResult::F_m_error was estimated.
enum class ErrorMethod {
    none,           ///< not estimated (estimate_error off, or the run failed)
    comparison_run, ///< a second run at another step (or tolerance): truncation error
    window_halves,  ///< a run that never settled: |max over first half - max over second
                    ///< half| of the recorded window, the sampling spread of F_m
};

/// "none", "comparison_run" or "window_halves".
std::string_view to_string(ErrorMethod method);

/// Everything one simulation reports.
struct SimulationResult {
    double F_m = 0.0;       ///< max over contacts and recorded time of the reduced force (eq 19)
    double F_m_error = 0.0; ///< estimated absolute error of F_m (see simulate())
    ErrorMethod error_method = ErrorMethod::none; ///< how F_m_error was estimated
    int F_m_contact = -1;                         ///< contact j where F_m occurred (-1: no contact)
    double F_m_time = 0.0;                        ///< reduced time of F_m
    bool contact = false;                    ///< whether any contact ever closed while recording
    std::vector<ContactMaximum> per_contact; ///< Nm + 1 entries, j = 0 left wall
    std::vector<BodyMaximum> per_body;       ///< Nm entries
    std::optional<int> steady_state_period;  ///< k if a periodic steady state was found
    std::optional<double> steady_state_time; ///< reduced time it was found at
    RunStatus status = RunStatus::completed; ///< how the main run ended
    std::string message;                     ///< failure explanation, empty on success
    Scheme scheme = Scheme::rk4;             ///< concrete scheme used
    double step = 0.0;                       ///< reduced time step used
    long periods_simulated = 0;              ///< forcing periods integrated in the main run
    long steps = 0;                          ///< steps in the main run
    long evaluations = 0;                    ///< right-hand-side evaluations, all runs
    std::vector<double> final_state;         ///< state at the end of the main run
    double wall_time_s = 0.0;                ///< wall time of the whole call [s]
};

/// Optional streams of one simulation.
struct SimulationHooks {
    TrajectorySink trajectory; ///< receives (decimated) states of the main run, if set
    int trajectory_every = 1;  ///< decimation in steps, >= 1
    ProgressCallback progress; ///< progress of the main run, if set
};

/// Simulates dyn from initial (2 Nm entries; empty = rest) under options.
///
/// F_m_error: when options.estimate_error, a second run at twice the step gives F_m'; the
/// estimate is |F_m - F_m'|, which bounds the error of F_m for any convergence order >= 1
/// (the true error is about |F_m - F_m'| / (2^p - 1)). In a chaotic regime it measures how
/// much the maximum over a finite run depends on the trajectory, which is the honest figure.
/// A harmonic run that ran its full length without settling skips the second run when the
/// maxima over the two halves of its recorded window differ by more than 10 * tolerance *
/// F_m: that difference, the sampling spread of the maximum, is then reported instead
/// (error_method says which).
SimulationResult simulate(const Dynamics& dyn, const RunOptions& options,
                          const std::vector<double>& initial = {},
                          const SimulationHooks& hooks = {});

} // namespace gapchain
