#pragma once
/// \file attractors.hpp
/// Coexisting attractors of the forced row: many starts, each run to its steady state (or to
/// the end of its run), grouped into attractors, with the F_m of each, its regime and period,
/// its basin fraction with a sampling error, and the design value F_m_max over them.
///
/// Starts are drawn uniformly in a box scaled by the contact-free amplitude A of eq (20) around
/// a center c (2 Nm entries; rest unless AttractorOptions::center says otherwise): u_i in
/// [c_i - box A, c_i + box A], v_i in [c_{Nm+i} - box 2 pi f_r A, c_{Nm+i} + box 2 pi f_r A]
/// (reduced units: A is the amplitude a free body would have, the natural scale of the motion). A
/// small box around a state of interest (an unstable orbit, a suspected small basin) searches its
/// neighbourhood.
///
/// Grouping. A start whose run reaches a periodic steady state is Newton-confirmed
/// (orbit.hpp); two periodic starts share an attractor when their orbits have the same minimal
/// period and pass through the same stroboscopic points (to 1e-6, relative). A start that does
/// not settle keeps the stroboscopic points of its last section_points periods; it joins an
/// attractor whose points it matches by a two-sample nearest-neighbour test: the median distance
/// from each of its points to the other cloud is at most overlap_factor times the larger median
/// nearest-neighbour distance inside either cloud. Two windows of one ergodic attractor sample
/// the same invariant measure, so their clouds interleave at the clouds' own point spacing;
/// disjoint attractors are separated by a distance that does not shrink as points are added.
/// A run that ends within 1e-2 (scaled) of a stable periodic attractor's points is still
/// converging to it and joins it. Each non-periodic group is confirmed by continuing the runs
/// of a few of its members (a sixteenth of the random starts, 3 to 8) from where they ended:
/// ten lifetimes of the search's transients beyond their median (its non-periodic starts
/// counted as still going), or ten run lengths where orbits were reached but no lifetime was
/// measured, or one; between one and ten run lengths, within run.max_work. If one of them
/// settles on an orbit, the group is a chaotic transient (a saddle), not an attractor: every
/// member is continued (as many as run.max_work affords, in start order), each start is counted
/// with the attractor it reached, and those still wandering stay in the group, marked
/// unsettled (Attractor::left_for_orbits). A continuation that reaches another non-periodic
/// group merges the whole group into it (two windows of one chaotic set).
///
/// Settling. Each start that settles on a periodic attractor reports where its transient ended:
/// the period from which on its state stayed within 1e-3 (relative) of repeating
/// (SimulationResult::cycle_entry_period). Where a chaotic saddle coexists with the attractors
/// these lifetimes are long and exponentially distributed (escape from the saddle is
/// memoryless); a run that records part of them reports the transient's F_m, which F_m_runs
/// shows.

#include "gapchain/classify.hpp"
#include "gapchain/model.hpp"
#include "gapchain/run.hpp"
#include "gapchain/simulation.hpp"
#include "gapchain/transient_lifetime.hpp"

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

namespace gapchain {

/// A two-variable slice of the basins: a resolution x resolution grid of starts over two state
/// variables, the others at the box's center (AttractorOptions::center; rest by default).
struct BasinSlice {
    int first = 0;       ///< state index of the x axis, 0 .. 2 Nm - 1 (u_1..u_Nm, v_1..v_Nm)
    int second = 1;      ///< state index of the y axis, 0 .. 2 Nm - 1, not first
    int resolution = 50; ///< grid points per axis, 2 .. 2000
};

/// How attractors are searched.
struct AttractorOptions {
    long samples = 200;     ///< random starts for the basin fractions, 1 .. 1e7
    std::uint64_t seed = 1; ///< seed of the starts, 0 .. 2^62
    double box = 1.0;       ///< half-width of the box of starts, in units of A, [1e-9, 100]
    /// Center of the box of starts and of the slice (2 Nm entries: u_1..u_Nm then v_1..v_Nm,
    /// reduced units, each in [-1e9, 1e9] as a scene's initial state); empty: rest.
    std::vector<double> center;
    /// Each start's run (steady-state stop on to finish early). Its estimate_error is taken as
    /// true and its multistability_check as false whatever they say: each start needs its
    /// F_m_error to be grouped, and the search itself replaces the twin.
    RunOptions run;
    int section_points = 200;    ///< stroboscopic points kept of a run that does not settle,
                                 ///< 20 .. 100000; a run recording fewer periods keeps
                                 ///< them all (one point per recorded period)
    double overlap_factor = 3.0; ///< nearest-neighbour test factor, 1 .. 100
    /// Periods of the lambda_max run of a non-periodic group, 10 .. 1e6; taken 4, 16 and 64
    /// times longer (within run.max_work) while it cannot tell a torus (within three errors of
    /// 0, the error at most chaos_threshold / 4) from chaos or from the approach to an orbit
    /// (more than three errors below 0)
    long lyapunov_periods = 300;
    /// lambda_max above this and 3 errors: chaotic [1 / time], 0 .. 1e3; a torus needs an
    /// error of a quarter of it at most (at 0 no group reads as a torus)
    double chaos_threshold = 0.02;
    std::optional<BasinSlice> slice; ///< also run the starts of this slice
    int threads = 0;                 ///< OpenMP threads (0: all); results do not depend on it
};

/// Throws std::invalid_argument naming the first option outside its range (Nm: the row's).
void validate(const AttractorOptions& options, int Nm);

/// The center of the box of starts as a search of a row of Nm bodies uses it: options.center,
/// or rest (2 Nm zeros) where it is empty. Reduced units.
std::vector<double> box_center(const AttractorOptions& options, int Nm);

/// The basin slice over the state variables named first and second ("u1".."uNm",
/// "v1".."vNm"), resolution points per axis. Throws std::invalid_argument naming "grid" for any
/// other name or the same name twice.
BasinSlice basin_slice(std::string_view first, std::string_view second, int Nm, int resolution);

/// The checks of find_attractors() on row p: p and options valid, and a recorded window
/// (run.periods - run.transient_periods, the latter resolved for p) of at least 20 periods, the
/// fewest section points that tell a non-periodic attractor from a transient. Throws
/// std::invalid_argument naming run.periods.
void validate(const ReducedParameters& p, const AttractorOptions& options);

/// One attractor.
struct Attractor {
    int id = 0;                       ///< 0, 1, ... in order of discovery (start index order)
    Regime regime = Regime::periodic; ///< periodic, quasi-periodic or chaotic (or no-contact)
    int period = 0;                   ///< minimal period [forcing periods]; 0 if not periodic
    /// False for a non-periodic group whose lambda_max is negative beyond max(chaos_threshold,
    /// 3 errors) (its runs were still converging to a stable orbit when they ended), that is
    /// not chaotic and whose lambda_max's error exceeds chaos_threshold (a torus, chaos and
    /// an approach not told apart), that never
    /// touched (the damped linear row has one attractor, a periodic one), or whose runs last
    /// less than four decay times of the contact-free row from the box's farthest start (eps
    /// near 0, or a center far from rest), or some of whose starts left it for an orbit when
    /// their runs were continued (left_for_orbits): its F_m is a transient's (raise
    /// run.periods). Shown as the regime "unsettled".
    bool settled = true;
    bool newton_confirmed = false; ///< periodic: the orbit converged under Newton
    double max_multiplier = 0.0;   ///< periodic: largest Floquet multiplier modulus
    /// periodic: its error (PeriodicOrbit::max_multiplier_error; NaN where not estimated)
    double max_multiplier_error = 0.0;
    double F_m = 0.0; ///< largest reduced impact force on the attractor
    /// A confirmed orbit: |F_m (exact propagator) - F_m (rk8pd at 1e-10)| on the orbit; an
    /// unconfirmed periodic one (F_m the run's orbit maximum, F_m_orbit): the run's F_m_error;
    /// otherwise the window-halves sampling spread of the member whose F_m is the largest.
    double F_m_error = 0.0;
    /// Largest Lyapunov exponent [1 / reduced time]; NaN for a periodic steady state Newton
    /// did not confirm (not computed: blank in CSV, null in JSON).
    double lambda_max = 0.0;
    double lambda_max_error = 0.0; ///< its standard error (a Newton-confirmed
                                   ///< orbit: from max_multiplier_error)
    double basin_fraction = 0.0;   ///< share of the random starts that reach it
    /// binomial standard error sqrt(p (1 - p) / N), at least 1 / N (N starts all alike bound
    /// the fraction to about that)
    double basin_fraction_error = 0.0;
    long samples = 0; ///< random starts that reach it
    /// A periodic attractor: the median over its random starts of the period where their
    /// transient ended (cycle_entry_period), counting those still_settling as longer than any;
    /// NaN if the median is one of those, for a non-periodic attractor, and for one that no
    /// random start reached (only slice starts).
    double settle_median = std::numeric_limits<double>::quiet_NaN();
    /// The longest of those periods over the starts that settled [forcing periods]; NaN if none.
    double settle_max = std::numeric_limits<double>::quiet_NaN();
    /// Random starts that reach it but whose runs ended still approaching it (a transient
    /// longer than run.periods); 0 for a non-periodic attractor.
    long still_settling = 0;
    /// The largest F_m the runs of its random starts recorded, over their windows after the
    /// discarded start-up (run.transient_periods): what single runs from those starts report,
    /// their transients included. Above F_m when transients outlast the discarded periods; NaN
    /// if no random start reached it.
    double F_m_runs = std::numeric_limits<double>::quiet_NaN();
    /// that run's F_m_error; NaN with F_m_runs
    double F_m_runs_error = std::numeric_limits<double>::quiet_NaN();
    long slice_points = 0; ///< slice starts that reach it
    /// A non-periodic group: its starts (random and slice) whose runs were continued to
    /// confirm it (AttractorSet::confirmation_periods more), those still in it and those that
    /// left for orbits (left_for_orbits); 0 for a periodic one. Where none left, only its 3 to
    /// 8 probes (and those of groups merged into it); once one left, every member, as many as
    /// run.max_work affords: below left_for_orbits + samples + slice_points where it did not
    /// afford them all, or a continuation failed
    long members_continued = 0;
    /// A non-periodic group: its starts whose continued runs left it for a periodic attractor;
    /// above 0 it is a chaotic transient that outlasts the runs, not an attractor (settled
    /// false), and the starts still in it when the continuation ended remain its members
    long left_for_orbits = 0;
    /// the first start that reached it (2 Nm); a chaotic transient's (left_for_orbits): the
    /// start of the member that stayed farthest from the stable orbits
    std::vector<double> initial_state;
    /// a state on it at phase 0 (the orbit's, if periodic; a chaotic transient's: where its
    /// lambda_max run started)
    std::vector<double> state;
    /// Stroboscopic points that identify it: the orbit's, or the first member's last points.
    std::vector<std::vector<double>> section;
};

/// The attractor's regime as written in results: to_string(regime), or "unsettled".
std::string_view regime_label(const Attractor& a);

/// The attractors found.
struct AttractorSet {
    std::vector<Attractor> attractors; ///< by id (0-based), in the order first reached
    /// The design value: the largest F_m over the attractors (the settled ones; over the
    /// unsettled groups only if none settled).
    double F_m_max = 0.0;
    int unsettled = 0;                 ///< attractors with settled false (F_m_max may be a
                                       ///< transient's then)
    double F_m_max_error = 0.0;        ///< that attractor's F_m_error
    int F_m_max_id = -1;               ///< the attractor it belongs to (-1: none)
    std::vector<int> sample_attractor; ///< per random start: attractor id, -1 if its run failed
    /// Per random start: the period where its transient ended (cycle_entry_period); -1 if its
    /// run did not settle on an orbit (a non-periodic attractor, still approaching, or failed).
    std::vector<long> sample_settle_period;
    std::vector<double> sample_F_m; ///< per random start: its run's F_m (0 if its run failed)
    /// How long the transients of the random starts that reached a periodic attractor lasted
    TransientLifetime transients;
    long failed = 0; ///< starts whose run failed (non-finite)
    /// Periods the continued members of each non-periodic group (Attractor::members_continued)
    /// were run on beyond their run.periods to confirm it (0: no such group). A group none of
    /// whose continued members left stands: no finite run rules out a transient longer than that
    long confirmation_periods = 0;
    std::vector<int> slice_attractor; ///< resolution^2, second axis slowest; -1: failed
    std::vector<double> slice_first;  ///< the slice's x values
    std::vector<double> slice_second; ///< the slice's y values
    double amplitude = 0.0;           ///< A of eq (20), the box's unit
    double wall_time_s = 0.0;         ///< [s]
    int threads_used = 1;             ///< threads the starts ran on (results do not depend on it)
    bool cancelled = false;           ///< progress asked to stop; nothing was grouped
    /// Whether some group settled on an attractor (F_m_max is then an attractor's, not a
    /// transient's).
    [[nodiscard]] bool any_settled() const { return attractor_count() > 0; }
    /// Settled groups: the attractors found (an unsettled group is a transient's)
    [[nodiscard]] int attractor_count() const {
        return static_cast<int>(attractors.size()) - unsettled;
    }
};

/// The starts of options (random ones, then the slice's) in the order they are grouped.
std::vector<std::vector<double>> attractor_starts(const ReducedParameters& p,
                                                  const AttractorOptions& options);

/// Searches the attractors of the paper's row p (harmonic forcing, linear law) from the starts
/// of attractor_starts(), in parallel; progress gets the fraction of starts run.
AttractorSet find_attractors(const ReducedParameters& p, const AttractorOptions& options,
                             const ProgressCallback& progress = {});

} // namespace gapchain
