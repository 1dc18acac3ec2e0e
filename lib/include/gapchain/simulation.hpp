#pragma once
/// \file simulation.hpp
/// One simulation of a row: F_m (eq 19) with its error estimate, per-contact and per-body
/// maxima, impact counts, the periodic steady state if any, and the run time.

#include "gapchain/dynamics.hpp"
#include "gapchain/observers.hpp"
#include "gapchain/run.hpp"

#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gapchain {

/// The larger of the left and right contact forces one body felt.
struct BodyMaximum {
    double left = 0.0;    ///< max reduced force from the contact on its left
    double right = 0.0;   ///< max reduced force from the contact on its right
    double t_left = 0.0;  ///< reduced time of the left maximum
    double t_right = 0.0; ///< reduced time of the right maximum
    /// Estimated errors of left and right: the per_contact_error of contacts i and i + 1
    /// (SimulationResult), NaN where it is empty (not estimated)
    double left_error = std::numeric_limits<double>::quiet_NaN();
    double right_error = std::numeric_limits<double>::quiet_NaN(); ///< see left_error
};

/// How SimulationResult::F_m_error was estimated.
enum class ErrorMethod {
    none,           ///< not estimated (estimate_error off, or the run failed)
    comparison_run, ///< a second run at another step (or tolerance): truncation error
    window_halves,  ///< a run that never settled: the sampling spread of F_m, the larger of
                    ///< |max over first half - max over second half| of the recorded window
                    ///< and the tail of its per-period maxima (MaxForceTracker::tail_spread())
    /// estimate_error off, but the start checks widened F_m_error: it is only the difference
    /// to the twin run's F_m or to the settled orbit's maximum (no truncation error in it)
    start_dependence,
};

/// "none", "comparison_run", "window_halves" or "start_dependence".
std::string_view to_string(ErrorMethod method);

/// Which accuracy a simulation's main run kept (see RunOptions::accuracy_mode).
enum class AccuracyUsed {
    strict,  ///< every step held to run.tolerance
    relaxed, ///< a run that did not settle, finished on the relaxed plan (see simulate())
};

/// "strict" or "relaxed".
std::string_view to_string(AccuracyUsed used);

/// Everything one simulation reports.
struct SimulationResult {
    double F_m = 0.0;       ///< max over contacts and recorded time of the reduced force (eq 19)
    double F_m_error = 0.0; ///< estimated absolute error of F_m (see simulate())
    ErrorMethod error_method = ErrorMethod::none; ///< how F_m_error was estimated
    int F_m_contact = -1;                         ///< contact j where F_m occurred (-1: no contact)
    double F_m_time = 0.0;                        ///< reduced time of F_m
    bool contact = false;                    ///< whether any contact ever closed while recording
    std::vector<ContactMaximum> per_contact; ///< Nm + 1 entries, j = 0 left wall
    /// Estimated absolute error of each per_contact[j].force (Nm + 1 entries): the larger of
    /// F_m_error and the contact's own difference against the comparison run, scaled as F_m's
    /// (a small inner contact can be known less well than F_m: 5e-5 against 2.9e-5 on Fig 5's
    /// scene). Empty where no comparison run estimated F_m_error (the window-halves spread of a
    /// run that never settles is F_m's, not each contact's; estimate_error off; cancelled).
    std::vector<double> per_contact_error;
    std::vector<BodyMaximum> per_body;       ///< Nm entries
    std::optional<int> steady_state_period;  ///< k if a periodic steady state was found
    std::optional<double> steady_state_time; ///< reduced time it was found at
    /// A run that found a steady state: the first period from which on its state stayed within
    /// SteadyStateDetector::far_distance (1e-3, relative) of repeating with some period up to
    /// run.max_steady_period, i.e. where its transient ended and the final approach began. The
    /// first max_steady_period periods are not tested: a run never seen far from a cycle reports
    /// max_steady_period + 1, or the period its steady state was found at if that is earlier.
    /// -1 without a steady state.
    long cycle_entry_period = -1;
    /// The last period whose state was more than SteadyStateDetector::far_distance (1e-3,
    /// relative) from repeating with every period up to run.max_steady_period, with or without
    /// a steady state [forcing periods]; -1 if none was (the first max_steady_period periods are
    /// not tested). A run without a steady state whose last_far_period is well before its end
    /// had ended its transient and was still approaching its cycle.
    long last_far_period = -1;
    /// A run that found no steady state but whose last two period states pass the steady-state
    /// test (run.steady_tolerance) with a lag k beyond run.max_steady_period (k up to 4 times it
    /// and 1000, within 32 MB of states: none on rows of more than about 250,000 bodies): k, the
    /// cycle it ended on, on which the same run with run.max_steady_period = k stops. Empty
    /// otherwise.
    std::optional<int> longer_cycle_period;
    RunStatus status = RunStatus::completed; ///< how the main run ended
    std::string message;                     ///< failure explanation, empty on success
    Scheme scheme = Scheme::rk4;             ///< concrete scheme used
    double step = 0.0;                       ///< reduced time step used
    long periods_simulated = 0;              ///< forcing periods integrated in the main run
    long transient_periods_used = 0;         ///< first periods discarded (not in the maxima)
    long steps = 0;                          ///< steps in the main run
    long evaluations = 0;                    ///< right-hand-side evaluations, all runs
    std::vector<double> final_state;         ///< state at the end of the main run
    /// Whether the twin run of the multistability check ran (see simulate()).
    bool twin_checked = false;
    /// The answer depends on the start (several attractors, or a transient longer than the
    /// run): the twin run's F_m disagreed with F_m beyond both runs' spreads, or a run that
    /// settled late took its maximum in the transient. F_m_error covers |F_m - F_m_twin| (as it
    /// does whenever the twin ran). gapchain-attractors gives the F_m of each attractor.
    bool multistable = false;
    /// The multistability check applied (run.multistability_check, harmonic forcing, a run
    /// that ran its course). Without it, multistable = false says nothing: written as JSON null,
    /// an empty CSV field, Python None.
    bool multistability_checked = false;
    double F_m_twin = 0.0; ///< the twin run's F_m (when twin_checked)
    /// The F_m of the error estimate's comparison run (error_method comparison_run: the same
    /// start on another plan, see simulate(); the half-step run where a periodic run had two);
    /// empty when none ran.
    std::optional<double> F_m_comparison;
    /// That comparison run ended elsewhere than a main run that settled on an orbit: it ran its
    /// full length without settling where the main run settled within half of it, or it settled
    /// on an orbit whose largest force differs by more than max(0.1, 1000 tolerance) of it. A
    /// chaotic transient that the other step followed differently can do that, and so can the
    /// coarser step's own dynamics; under options.multistability_check the twin run then
    /// decides (as for a run that settled late).
    bool comparison_ended_elsewhere = false;
    /// A run that settled on a periodic orbit (harmonic forcing; see simulate()): the largest
    /// force over one cycle of that orbit, >= 0.
    std::optional<double> F_m_orbit;
    /// F_m_orbit's error estimate, from the comparison run where it settled on the same orbit
    /// (see simulate()); empty where none did, or the error was not estimated. Start checks
    /// do not widen it, as they widen F_m_error: another attractor does not move this orbit.
    std::optional<double> F_m_orbit_error;
    /// F_m_orbit is below F_m by more than the accuracy asked (max(tolerance, 1e-9) F_m): the
    /// maximum fell before the orbit was reached (a start-up that decays slower than MODEL.md §2's
    /// discarded periods assume, or a chaotic transient; the latter is also multistable). F_m_error
    /// covers F_m - F_m_orbit.
    bool maximum_in_transient = false;
    /// A harmonic run that did not settle: the periods the contact-free row's start-up takes
    /// to decay to run.tolerance (default_transient_periods() without its cap; 1e9 where
    /// nothing decays, eps = 0); 0 for a run that settled.
    long start_up_periods = 0;
    /// The run did not settle and discarded fewer periods than start_up_periods: its window
    /// holds the start-up, so F_m may be the start-up's (eps near 0, a run too short for its
    /// damping; raise run.periods).
    bool start_up_in_window = false;
    /// Whether the main run kept to the tolerance throughout or finished relaxed.
    AccuracyUsed accuracy_mode_used = AccuracyUsed::strict;
    long relaxed_from_period = -1; ///< period the relaxed plan took over at (-1: strict)
    double wall_time_s = 0.0;      ///< wall time of the whole call [s]
};

/// Whether r.F_m_error holds an estimate. False when nothing estimated it (error_method none:
/// run.estimate_error off and no check widened it, or a run that failed), where a 0 would read
/// as an exact F_m:
/// reports then write null (JSON), an empty field (CSV), None or NaN (Python).
[[nodiscard]] bool has_error_estimate(const SimulationResult& r);

/// Optional streams of one simulation. A trajectory sink or any observer keeps a run in
/// AccuracyMode::automatic on the strict plan throughout (no relaxed part): what they are fed
/// is then the strict dynamics, and F_m may differ, within its error bar, from the same run
/// without hooks.
struct SimulationHooks {
    TrajectorySink trajectory;        ///< receives (decimated) states of the main run, if set
    int trajectory_every = 1;         ///< decimation in steps, >= 1
    ProgressCallback progress;        ///< progress of the main run, if set
    std::vector<Observer*> observers; ///< further observers of the main run (not owned)
};

/// The most trajectory values (rows x (1 + 2 Nm) columns) one run may record: 2.5e8, 2 GB as
/// doubles in memory, about 5 GB as CSV.
inline constexpr double max_trajectory_values = 2.5e8;

/// Throws std::invalid_argument naming output.trajectory_every and run.periods, with the
/// estimated rows and their size, when a run of options on dyn recording every `every`-th step
/// (>= 1) after its transient would hold more than max_trajectory_values: a long run's
/// trajectory filled the memory (Python) or the disk (CSV) after its work check had passed.
/// Rows are counted as the recorded periods' planned steps and contact switches
/// (contact_switches_per_period()), each a piece of a split step, / every.
void require_trajectory_fits(const Dynamics& dyn, const RunOptions& options, int every);

/// Simulates dyn from initial (2 Nm entries; empty = rest) under options; an auto transient is
/// resolved by with_transient_resolved() (result.transient_periods_used).
///
/// F_m_error (when options.estimate_error), error_method says which:
/// - window_halves: a harmonic run that ran its full length without settling, whose sampling
///   spread (the larger of its window halves' maxima's difference and the spread read from
///   the tail of its per-period maxima, MaxForceTracker::tail_spread()) exceeds
///   10 * tolerance * F_m, reports that spread: how far a maximum over a finite window moves.
///   A run that never settled gets at least it whichever method stands.
/// - comparison_run otherwise: a second run on another plan gives F_m'. Fixed-step schemes
///   compare a periodic run whose F_m is its orbit's (no more than max(tolerance, 1e-9) F_m
///   above F_m_orbit) at half the step and at twice it (rk4's default step is often not yet
///   in its asymptotic order: docs/accuracy.md), and report the larger of 2 |F_m - F_m'| /
///   (1 - 2^-p) (half the step) and 2 |F_m - F_m''| / (2^p - 1) (twice it): Richardson with
///   a safety factor of 2, p the scheme's order (at most 1.5 under a p^(3/2) contact law,
///   whose F_m converges erratically: docs/accuracy.md); F_m' is a comparison run's orbit maximum
///   over one cycle where that run took its own maximum in the transient, and the bar then also
///   covers how far that run's window maximum lies above F_m (its path's start-up reached into
///   the window). Where the half-step run does not settle on that orbit, 2 |F_m - F_m'|; where
///   the run at twice the step ends elsewhere, |F_m - F_m''| at least. Others - a run that did not
///   settle, one that took its maximum in the transient - compare at twice the step (half, if
///   twice breaks the stability limit) and report 2 |F_m - F_m'|: a maximum taken in a
///   transient is not a truncation error (a chaotic transient followed differently at the
///   other step), and the run at h is no nearer the truth than the other. rkf45/rk8pd
///   compare at ten times the tolerance and twice the output interval (their largest step),
///   exact at half the output interval; on their orbit they report |F_m - F_m'|, else twice
///   it. A ground motion record's run compares at half the step (a tenth of an adaptive
///   tolerance, half its output interval) and reports 2 |F_m - F_m'|: its transient follows one
///   path at h and 2h where the truncation error decides it (docs/beyond.md). The estimate is
///   never below a round-off floor, exact_F_m_round_off F_m (1e-12 F_m,
///   stepper.hpp) for every scheme. F_m_orbit_error comes from the same comparison run where
///   it settled on the same
///   orbit (for a run on its orbit, the larger of F_m_error's estimate and the orbits'
///   difference under the same factor; otherwise twice the orbits' difference, Richardson's
///   factor for a run at half the step).
///
/// Transient check (harmonic forcing; with options.estimate_error, and for a run that settled
/// late also under the multistability check): a run
/// that settled on a periodic orbit is continued for one cycle of it; F_m_error covers any
/// excess of F_m over the orbit's largest force (F_m_orbit), and an excess beyond the accuracy
/// asked, max(options.tolerance, 1e-9) F_m, means F_m came from the transient
/// (maximum_in_transient; both runs share one plan, so F_m_error does not enter the test, except
/// for a run that finished on the relaxed plan: also beyond 3 F_m_error). The
/// cost is one orbit cycle (k periods) per periodic run.
///
/// Multistability check (options.multistability_check, harmonic forcing): a run that settled
/// late and took its F_m in the transient is multistable (the maximum is a property of the
/// start: a chaotic transient before the orbit). Then a run that did
/// not settle quickly - no steady state, or one reached only after the state stayed far (1e-3,
/// relative) from every cycle for longer than it then took to converge, the mark of a chaotic
/// transient - or whose comparison run (same start, another step) ended elsewhere
/// (comparison_ended_elsewhere: a transient that settled early in this run but not in that
/// one) is repeated from the start with u_1 moved by 1e-8 max(1, |x0|). If the twin's
/// F_m differs from F_m by more than max(3 F_m_error, 3 x either run's window-halves spread,
/// 1e-6 F_m), the result is multistable; F_m_error always covers the difference (the twin's
/// answer is as valid as the main run's). A quickly settled run (the usual
/// periodic point) runs no twin: its cost is the transient check's one orbit cycle (and the
/// comparison run's).
///
/// Accuracy (options.accuracy_mode): in `automatic`, a run on the automatic scheme and step
/// that, at four times the contact-free row's decay time to 1e-3 (and after the transient and
/// max_steady_period + 8 periods), has no steady state, is farther than 1e-3 (relative) from
/// every cycle of up to max_steady_period periods, and whose distance to the nearest cycle did
/// not fall a thousandfold over the last 8 periods, and whose strict head took at least 1.25
/// times the relaxed plan's right-hand sides per period (else relaxing gains nothing its checks
/// do not cost again), finishes on a relaxed plan (stopped and
/// redone strict as soon as it comes within 1e-6 of a cycle):
/// rk4 at h omega_max = 0.4, steps not split at contact switches, whatever the tolerance (its
/// F_m error, 1.4e-3 F_m rms on periodic points of the paper's grid, is credited as 3e-3 F_m).
/// Its answer stands only if the run then never settles and either its window-halves spread is
/// at least that, 3e-3 F_m, or its twin - from the state it relaxed at, moved by 1e-8, over the
/// relaxed part only - runs to the same end without settling, ends more than 1e-2 x max(1,
/// |y|_inf) away (chaos; a torus keeps it about 1e-8 away) and has an F_m within 3 x the larger
/// of the two spreads and 3e-3 F_m; and first of all, the strict dynamics continued from its
/// end for a fifth of the relaxed part (at least max_steady_period + 32 periods; a run too short
/// for that does not relax) neither come within 1e-3 of a cycle nor approach one: the relaxed
/// plan's dynamics are not the strict plan's, and it can keep a row on a chaotic saddle that the
/// strict dynamics leave (17 of 270 relaxed answers of a 2000-point sample of the paper's grid,
/// 15 of them caught this way; escape from a saddle is memoryless, so a slow one can pass,
/// docs/performance.md). Otherwise the
/// run is done again in strict mode, so a quasi-periodic answer, and a periodic one of the
/// strict dynamics the relaxed plan reached, is a strict one. A relaxed answer's F_m_error
/// (window_halves) is the largest of its sampling spread, that twin's and 3e-3 F_m (and the
/// twin's difference). The multistability check's twin of a relaxed run is that twin (run if it
/// was not). A cancel through hooks.progress ends the call in any phase. `strict` keeps every run
/// to the tolerance. result.accuracy_mode_used says which answer came back.
SimulationResult simulate(const Dynamics& dyn, const RunOptions& options,
                          const std::vector<double>& initial = {},
                          const SimulationHooks& hooks = {});

/// The work check simulate() makes before it starts (std::invalid_argument naming run.max_work
/// with the estimate): the main run, and where options.estimate_error asks, its comparison run
/// at the most it can take (twice the steps where the run may settle on an orbit: a
/// steady-state stop and harmonic forcing), which would otherwise be refused only after the
/// main run. A sweep makes it for its points before it writes a file.
void require_simulation_affordable(const Dynamics& dyn, const RunOptions& options);

/// The most whole forcing periods (>= 0) a run with options may last and pass
/// require_simulation_affordable(): its comparison run included where options.estimate_error
/// asks. Throws std::invalid_argument for invalid options.
double affordable_simulation_periods(const Dynamics& dyn, const RunOptions& options);

} // namespace gapchain
