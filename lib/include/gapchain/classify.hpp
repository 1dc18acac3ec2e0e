#pragma once
/// \file classify.hpp
/// Regime classification of a parameter point (no contact, periodic with its period,
/// quasi-periodic, chaotic) from the largest Lyapunov exponent and its error, the stroboscopic
/// section and the spectrum; and regime maps over (e_r, f_r) as in Fig 2 of the paper.
///
/// Rule: no impact while recording -> no-contact; a periodic steady state (state repeating to
/// steady_tolerance) -> periodic; otherwise lambda_max > max(chaos_threshold, 3 error) ->
/// chaotic; a repeating section or lambda_max < -max(...) -> periodic; else quasi-periodic.

#include "gapchain/model.hpp"
#include "gapchain/run.hpp"
#include "gapchain/stepper.hpp"

#include <memory>
#include <string_view>
#include <vector>

namespace gapchain {

/// The regime of a point.
enum class Regime { no_contact, periodic, quasi_periodic, chaotic };
/// "no-contact", "periodic", "quasi-periodic" or "chaotic".
std::string_view to_string(Regime regime);

/// How a point is classified.
struct ClassifyOptions {
    long transient_periods = 100; ///< discarded periods (a periodic steady state may stop the
                                  ///< run as soon as it is found), >= 0
    long record_periods = 300;    ///< periods of evidence for non-periodic motion, >= 20
    /// Integration scheme (run.scheme). `auto` is the exact propagator where the Lyapunov
    /// spectrum takes it (tangent_run_scheme(): linear contacts, harmonic forcing, <= 10
    /// bodies), else the simulator's `auto`.
    Scheme scheme = Scheme::automatic;
    double tolerance = 1e-4;                 ///< integration tolerance (relative, F_m)
    double max_work = RunOptions{}.max_work; ///< body-steps the run may take (run.max_work)
    /// Largest period recognised, >= 1: by the steady state up to max_period, by the
    /// repetition of the record's second half up to min(max_period, record_periods / 4); where
    /// lambda_max lies 3 errors below 0 (an attracting cycle, not a torus), up to
    /// record_periods / 8 (at most 1000) too.
    int max_period = 16;
    double period_tolerance = 1e-6; ///< section points closer than this (relative) are one
    double steady_tolerance = 1e-9; ///< state repeat tolerance for an early periodic stop
    /// Samples of u_1 per period for the spectrum, 4 .. 4096; the run records twice as many,
    /// to measure what the asked rate folds back (Classification::broadband_share_error)
    int samples_per_period = 16;
    double chaos_threshold = 0.02; ///< lambda_max must exceed this [1 / reduced time] and three
                                   ///< standard errors to count as chaos
    /// Confirm a periodic regime by Newton shooting (orbit.hpp) from the final state: the
    /// period becomes the orbit's minimal period, and its largest Floquet multiplier is given.
    bool confirm_by_newton = true;
    /// On a quasi-periodic or chaotic label, classify again from a start moved by 1e-8 (the
    /// twin, as gapchain-sim's multistability check): a chaotic transient that outlasts the
    /// record, or coexisting attractors, give the twin another label or F_m (start_dependent),
    /// and two samples of one chaos give lambda_max and F_m a spread their error bars cover.
    /// Doubles the cost of such points; periodic and no-contact labels run no twin.
    bool twin_check = true;
    /// Start of the run (of every cell of a map): 2 Nm reduced numbers (u then v, relative to
    /// the ground), finite; empty: rest.
    std::vector<double> initial;
    /// Keep the whole state at each stroboscopic point of a record that never settled
    /// (Classification::section_states): what label_in_search() sets against an attractor
    /// search's groups. Off for maps (2 Nm x record_periods doubles a cell).
    bool keep_section_states = false;
};

/// Throws std::invalid_argument naming the first invalid option.
void validate(const ClassifyOptions& options);

/// The run of each start of an attractor search set against a classification: as long as the
/// classification's (transient_periods discarded of transient_periods + record_periods), with
/// its scheme, tolerance and max_work, steady cycles tried up to its max_period, and every other
/// run option at its default, since a classification reads no other run key.
RunOptions classify_search_run(const ClassifyOptions& options);

/// The label and its evidence.
struct Classification {
    Regime regime = Regime::no_contact;
    int period = 0; ///< forcing periods per cycle when periodic; 0 when the cycle
                    ///< is longer than max_period (or not periodic)
    /// Largest Lyapunov exponent [1 / reduced time]: ln(max_multiplier) / (period T) for an
    /// orbit Newton confirmed, else the tangent vector's average along the run (for a periodic
    /// label without Newton, along at least 20 periods of the orbit, restarted at the settle;
    /// where Newton was asked and did not confirm it, along at least 20 periods after its
    /// recorded cycle, unless those are beyond max_work: then one cycle's, with no error).
    double lambda_max = 0.0;
    double lambda_max_error = 0.0; ///< the average's standard error (inf if the window was too
                                   ///< short); for a confirmed orbit, from its largest
                                   ///< multiplier's error (max_multiplier_error); at
                                   ///< least the twin's difference (start_dependent)
    int distinct_points = 0;       ///< distinct stroboscopic points among those recorded
    int section_points = 0;        ///< stroboscopic points recorded
    /// Share of u_1's spectral power away from m/n f_r (n <= 4), [0, 1], on Welch segments of
    /// whole periods (whole_period_segment(), four at least); read only where the run did not
    /// settle (0 on a periodic steady state, or a record too short: fewer than 256 samples, or
    /// segments of so few periods that most bins lie next to some m/n f_r, about 70 recorded
    /// periods or fewer)
    double broadband_share = 0.0;
    /// Its estimated error, >= 0: the Welch segments' spread (broadband_share_error() of
    /// spectrum.hpp) plus the aliased share plus its move on segments of half the periods
    /// (broadband_share_resolution_error()); 0 where the share was not read for a settled
    /// state, NaN where the record was too short to read it
    double broadband_share_error = 0.0;
    /// Max reduced force: over the orbit Newton confirmed (newton_confirmed), else over the
    /// recorded periods.
    double F_m = 0.0;
    /// Error estimate of F_m, >= 0: on a periodic state (recorded over one orbit cycle) the
    /// accuracy the run is held to, tolerance * F_m, and after a settle in the record at least
    /// the record's maximum's excess over it (settled_in_record); otherwise the sampling spread
    /// |max over the first half - max over the second half of the recorded periods| and the spread
    /// of the tail of its per-period maxima (MaxForceTracker::tail_spread()), at least that; for a
    /// confirmed orbit also at least its difference from the recorded maximum; where the twin
    /// ran its course, at least its difference from the twin's F_m.
    double F_m_error = 0.0;
    /// On a point labelled quasi-periodic or chaotic: the periods the contact-free row's
    /// start-up takes to decay to the tolerance (start_up_decay_periods(); 1e9 where nothing
    /// decays, eps = 0); 0 otherwise.
    long start_up_periods = 0;
    /// start_up_periods exceeds the discarded periods: the record may hold the start-up, not
    /// the regime (eps = 0.001: chaotic, F_m 2.64 +- 0.31 after 100 periods, 4.15 +- 0.31 after
    /// 6000); raise transient_periods.
    bool start_up_in_record = false;
    /// The twin of options.twin_check, where one ran (a quasi-periodic or chaotic label): the
    /// classification from a start moved by 1e-8 (u_1 by 1e-8 max(1, max_i |x0_i|)), itself
    /// without a twin. Its status says whether it ran its course.
    std::shared_ptr<const Classification> twin;
    /// The twin ran its course (status completed), and start_dependent is its verdict. False
    /// where no twin ran, or where it went non-finite or was cancelled (no verdict).
    bool twin_checked = false;
    /// The label depends on the start: the twin's label differs (a chaotic transient that
    /// outlasts the record, coexisting attractors, or a label at the margin of its rule), or
    /// its F_m differs by more than three times the larger of the two F_m_error before either
    /// covered the other. F_m_error covers |F_m - twin F_m| whenever the twin ran its course,
    /// and where the labels agree lambda_max_error covers |lambda_max - twin lambda_max| (the
    /// 10-block standard error alone read about 3x small on intermittent chaos). False is "not
    /// detected", not a confirmation: a transient that outlasts both runs reads alike in both.
    bool start_dependent = false;
    /// The state settled on a periodic steady state while recording, after more than
    /// transient_periods (a slow approach, or a chaotic transient that outlasted them): the
    /// label is the steady state's, from one cycle recorded after it (periods_run counts the
    /// record up to there); F_m is the cycle's (the orbit's where Newton confirmed it), and its
    /// error bar covers the record's maximum before the settle (the transient's, so it depends
    /// on transient_periods); without Newton (confirm_by_newton false), lambda_max is a
    /// tangent average restarted at the settle, over whole cycles of at least 20 periods, with
    /// their blocks' error (with Newton asked, over one cycle, no error, until Newton gives it;
    /// where Newton does not confirm the state, over at least 20 periods after that cycle;
    /// periods_run counts them).
    bool settled_in_record = false;
    bool stopped_at_steady_state = false; ///< the run ended early on a periodic steady state
    bool newton_confirmed = false; ///< Newton converged on the periodic orbit (period is then its
                                   ///< minimal period)
    double max_multiplier = 0.0;   ///< largest Floquet multiplier modulus (when confirmed)
    long periods_run = 0;          ///< periods integrated (the twin's not included)
    Scheme scheme_used =
        Scheme::rk4; ///< the concrete scheme the run took (options.scheme resolved)
    /// The tolerance the run kept (options.tolerance, or max_tangent_run_tolerance where that
    /// is tighter and the scheme is not exact: the tangent vector needs it).
    double tolerance_used = 0.0;
    RunStatus status = RunStatus::completed;
    double wall_time_s = 0.0; ///< [s], the twin's included
    /// With ClassifyOptions::keep_section_states, the whole state (u then v, 2 Nm reduced
    /// values) at each stroboscopic point of a record that never settled, in time order; empty
    /// otherwise.
    std::vector<std::vector<double>> section_states;
};

/// Classifies one point: one run with the max-force tracker, the steady-state detector, a
/// one-vector tangent observer, a stroboscopic section and a u_1 recorder. keep_going is asked
/// as the run advances (its argument is not a fraction of this point); false stops it with
/// status cancelled.
Classification classify(const ReducedParameters& p, const ClassifyOptions& options,
                        const ProgressCallback& keep_going = {});

/// A regime map over e_r (rows) and f_r (columns).
struct RegimeMap {
    std::vector<double> e_r;           ///< row values
    std::vector<double> f_r;           ///< column values
    std::vector<Classification> cells; ///< e_r-major: cell (i, j) at i * f_r.size() + j
    double wall_time_s = 0.0;          ///< [s]
    int threads_used = 1;              ///< OpenMP threads that ran it
    bool cancelled = false; ///< the progress callback stopped it; cells not run have status
                            ///< cancelled
};

/// Classifies every (e_r, f_r) around base in parallel (OpenMP, dynamic schedule; threads 0 =
/// all). Results do not depend on the thread count. Progress is called with the fraction done
/// (serialised), also while a cell runs, so that a cancel stops a long cell.
RegimeMap regime_map(const ReducedParameters& base, const std::vector<double>& e_r,
                     const std::vector<double>& f_r, const ClassifyOptions& options,
                     int threads = 0, const ProgressCallback& progress = {});

} // namespace gapchain
