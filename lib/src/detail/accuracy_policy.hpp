#pragma once
// One run of simulate() under the accuracy policy (RunOptions::accuracy_mode): in `auto` a run
// that still wanders after its strict head finishes on the relaxed plan, and its answer stands
// only if the strict dynamics continued from its end still wander (and, where its halves
// barely spread, a relaxed twin agrees); otherwise the run is done again strict. simulate()
// builds its error estimate and checks on the runs made here (simulation.cpp).

#include "gapchain/observers.hpp"
#include "gapchain/run.hpp"
#include "gapchain/simulation.hpp"

#include <memory>
#include <optional>
#include <vector>

namespace gapchain::detail {

/// What one run found: its outcome, maxima, steady state and end state.
struct SingleRun {
    RunOutcome outcome;
    std::vector<ContactMaximum> contacts;
    double F_m = 0.0;
    std::optional<int> period;
    std::optional<double> period_time;
    long evaluations = 0;
    double first_half_max = 0.0;     ///< largest force in the first half of the recorded window
    double second_half_max = 0.0;    ///< and in the second half
    double tail_spread = 0.0;        ///< MaxForceTracker::tail_spread() of the recorded window
    long last_far_period = -1;       ///< see SteadyStateDetector::last_far_period()
    std::optional<int> longer_cycle; ///< see SteadyStateDetector::longer_cycle()
    std::vector<double> final_state;
    long relaxed_from = -1;          ///< period the relaxed plan took over at (-1: strict run)
    std::vector<double> relax_state; ///< the state there
    double relax_time = 0.0;         ///< and its reduced time
    /// The twin run_settled() ran to test a relaxed answer whose halves barely spread (its
    /// evaluations are in this run's); empty if none.
    std::shared_ptr<const SingleRun> twin;
};

/// Relative F_m error credited to the relaxed plan: on 300 periodic points of the paper-scale
/// grid its F_m differed from strict runs at 1e-6 by 1.4e-3 rms (mean +3e-4, largest 1.3e-2;
/// docs/performance.md). A relaxed answer stands only with a sampling spread (its F_m_error) at
/// least that large.
constexpr double relaxed_error = 3e-3;

/// A run's own sampling spread: the maxima of its window halves, if it ran its full length.
double window_spread(const SingleRun& r);

/// One run of options from the planned start. In AccuracyMode::automatic a run that still
/// wanders (no cycle near, none approached) after its strict head, where the strict plan costs
/// enough more than the relaxed one, finishes on relaxed_plan(); relaxed_from says where.
SingleRun run_once(const Dynamics& dyn, const RunOptions& options, PlannedRun& planned,
                   const SimulationHooks& hooks = {});

/// x with its first entry moved by 1e-8 max(1, |x|_inf): the twin's start.
std::vector<double> perturbed(std::vector<double> x);

/// The twin of a relaxed main run: the relaxed part again, from the state the main run
/// relaxed at, perturbed. That start shares the main run's past, so the twin tests the same
/// question (does another nearby start end elsewhere?) at the cost of the relaxed part only.
SingleRun relaxed_twin(const Dynamics& dyn, const RunOptions& options, const SingleRun& main,
                       const ProgressCallback& progress);

/// run_once() from initial on a fresh plan (into planned), run again in strict mode where a
/// relaxed answer does not stand: the strict dynamics continued from its end come near a cycle,
/// or its halves barely spread and a relaxed twin does not show it chaotic and in agreement.
SingleRun run_settled(const Dynamics& dyn, RunOptions options, const std::vector<double>& initial,
                      const SimulationHooks& hooks, std::optional<PlannedRun>& planned);

} // namespace gapchain::detail
