#pragma once
/// \file bifurcation.hpp
/// Bifurcation diagrams: sweep one parameter, and at each value discard a transient, record
/// the section points of the chosen variables and F_m, and detect the period.

#include "gapchain/model.hpp"
#include "gapchain/poincare.hpp"
#include "gapchain/run.hpp"
#include "gapchain/stepper.hpp"

#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace gapchain {

/// How the values of a sweep are linked.
enum class SweepMode {
    independent,  ///< each value from the initial state; values run in parallel (OpenMP)
    continuation, ///< each value from the previous end state, from `from` to `to` and back (rows
                  ///< labelled up where the value grows)
};
/// Parses "independent" or "continuation"; throws std::invalid_argument otherwise.
SweepMode parse_sweep_mode(std::string_view name);

/// Sweep direction of a diagram row.
enum class SweepDirection { up, down };
/// "up" or "down".
std::string_view to_string(SweepDirection d);

/// What a diagram computes.
struct BifurcationOptions {
    SweptParameter parameter = SweptParameter::f_r; ///< swept parameter
    /// First value, in the parameter's reduced units, in its model range
    /// (validate(ReducedParameters)).
    double from = 2.0;
    double to = 4.5; ///< last value, same units and range; = from only with steps = 1
    int steps = 500; ///< number of values, >= 1 (ends included)
    SweepMode mode = SweepMode::independent; ///< each value from the start, or continued
    long transient_periods = 200;            ///< discarded periods per value, >= 0
    long record_periods = 100;               ///< recorded periods per value, >= 1
    SectionSpec section;                     ///< default: stroboscopic at phase 0, recording u_1
    Scheme scheme = Scheme::automatic;       ///< integration scheme
    double tolerance = 1e-4;                 ///< relative accuracy asked of each run
    /// Body-steps the whole diagram may take (run.max_work): its runs and their runs on the
    /// finer plan, at the costlier end's steps per period, refused up front above it.
    double max_work = RunOptions{}.max_work;
    double period_tolerance = 1e-6; ///< relative tolerance telling section points apart
    int max_period = 16;            ///< largest period detected, >= 1
    /// A periodic value's orbit is confirmed by Newton on the exact scheme from the run's end
    /// (confirm_periodic_orbit()): its minimal period, multipliers and F_m replace the
    /// window's readings. Rows the exact scheme refuses, whose shooting exceeds max_work, or
    /// where Newton does not converge on a stable orbit near the run's state keep the window's,
    /// and run the window again on a finer plan (BifurcationRow::F_m_error); a confirmed row
    /// runs it too, to check that it reaches the same orbit (BifurcationRow::ended_elsewhere).
    bool confirm_by_newton = true;
    int threads = 0; ///< OpenMP threads for independent mode (0: all)
    /// Start of every value (independent mode) or of the first (continuation mode): 2 Nm
    /// reduced numbers (u then v, relative to the ground), finite; empty: rest.
    std::vector<double> initial;
};

/// Throws std::invalid_argument naming the first invalid option.
void validate(const BifurcationOptions& options, const ReducedParameters& base);

/// One parameter value of one sweep direction.
struct BifurcationRow {
    double value = 0.0; ///< parameter value
    SweepDirection direction = SweepDirection::up;
    /// The recorded section points, in time order; where points_from_orbit, one cycle of the
    /// confirmed orbit's instead.
    std::vector<SectionPoint> points;
    /// The points are one cycle of the orbit Newton confirmed, on the exact scheme, timed over
    /// the run's last cycle: its minimal period was shorter than the window's (the row's scheme
    /// settled on a cycle the exact dynamics do not have: rk4's period 4 at f_r = 4.1092 on
    /// Fig 13's row, about an exact period-2 orbit).
    bool points_from_orbit = false;
    /// Max reduced force, >= 0: over the orbit Newton confirmed (newton_confirmed), else over
    /// the recorded periods.
    double F_m = 0.0;
    /// Error estimate of F_m, >= 0: the sampling spread |max over the first half - max over the
    /// second half of the recorded periods| (the error of a run that never settles) and, on a
    /// value not periodic, MaxForceTracker::tail_spread(), at least tolerance * F_m (the
    /// accuracy each run is held to, docs/accuracy.md); on a confirmed orbit also at least the
    /// recorded maximum's difference from the orbit's (the row's scheme's truncation error, or
    /// a start-up still in the window); on a row that is not periodic, and on a periodic row
    /// Newton did not confirm (with confirm_by_newton), also at least twice its difference from
    /// the same window on a finer plan (twice the steps, or a hundredth of an adaptive scheme's
    /// tolerance and half its output interval; skipped where that run alone exceeds max_work),
    /// and on a confirmed orbit that finer window did not reach (ended_elsewhere) too.
    double F_m_error = 0.0;
    /// Period in forcing periods (0: not periodic): the orbit's minimal period where Newton
    /// confirmed it, else the section's (SectionRepeats).
    int period = 0;
    bool newton_confirmed = false; ///< Newton converged on the row's periodic orbit
    /// A confirmed orbit that the same window on a finer plan (as F_m_error's) does not reach:
    /// that window's maximum differs from the orbit's F_m by more than ten times F_m_error and
    /// 1e-3 of the larger. The start lies so near a basin boundary that the scheme's own error
    /// picks the attractor (Nm 3, fc 100, eps 0.2, e_r 0.1 from rest, on the line 3.40-3.50 in
    /// 11 values: rk4 settles contact-free at 3.49, where the exact scheme reaches an impacting
    /// orbit of F_m 1.742); F_m_error then covers twice the difference. One finer run catches
    /// a start the two plans send different ways only: at 3.45 both reach the impacting orbit
    /// where the exact scheme settles contact-free. False where no finer run ran (not confirmed, or
    /// that run alone beyond max_work).
    bool ended_elsewhere = false;
    /// Largest Floquet multiplier modulus of the confirmed orbit (its minimal-period map);
    /// NaN unless newton_confirmed.
    double max_multiplier = std::numeric_limits<double>::quiet_NaN();
    RunStatus status = RunStatus::completed; ///< how the run ended
};

/// A whole diagram.
struct BifurcationResult {
    std::vector<BifurcationRow> rows; ///< up sweep in order, then the down sweep if any
    double wall_time_s = 0.0;         ///< wall time of the whole call [s]
    int threads_used = 1;             ///< OpenMP threads that ran it
    bool cancelled = false;           ///< the progress callback stopped it; rows not run or stopped
                                      ///< part-way have status cancelled and no points or maxima
                                      ///< (independent) or are missing (continuation)
};

/// Computes the diagram around base (its swept parameter is replaced by each value). Progress
/// reports the fraction of values done (it may be called from any thread, never concurrently).
/// Results do not depend on the number of threads.
BifurcationResult bifurcation(const ReducedParameters& base, const BifurcationOptions& options,
                              const ProgressCallback& progress = {});

} // namespace gapchain
