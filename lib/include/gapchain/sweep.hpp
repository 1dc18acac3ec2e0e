#pragma once
/// \file sweep.hpp
/// Parametric studies: a base scene, axes of values for any scene keys, a sampling of their
/// product (full grid, seeded random, Latin hypercube), and a parallel driver that streams one
/// result per point as it finishes. Every point is computed independently from its index, so
/// results do not depend on the thread count, the order or the shard.

#include "gapchain/attractors.hpp"
#include "gapchain/classify.hpp"
#include "gapchain/run.hpp"
#include "gapchain/simulation.hpp"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace gapchain {

/// One swept scene key ("model.fc", "excitation.f_r", ...) and its values.
struct StudyAxis {
    std::string key;            ///< "section.key"; the short names Nm, fc, eps, e_r, f_r work too
    std::vector<double> values; ///< at least one, all finite
};

/// How the points are drawn from the product of the axes.
enum class Sampling {
    grid,            ///< the full Cartesian product
    random,          ///< `samples` points, each axis value drawn uniformly (seeded)
    latin_hypercube, ///< `samples` points, each axis's values spread evenly (seeded)
};

/// Result fields a study keeps (F_m and the parameters always).
struct KeptResults {
    bool per_body = false;    ///< per-body left/right maxima
    bool regime = false;      ///< regime, period, lambda_max and its error (classification run)
    bool steady_state = true; ///< steady-state period
    bool wall_time = true;    ///< wall time per point
    /// F_m_orbit (the settled orbit's largest force; empty if the run did not settle), its
    /// error F_m_orbit_error (empty where not estimated) and maximum_in_transient (0/1: F_m fell
    /// before that orbit was reached; see simulate())
    bool orbit = false;
};

/// A study.
struct Study {
    std::string scene_json = "{}";      ///< the base scene (JSON text)
    std::vector<StudyAxis> axes;        ///< in order; the first varies slowest on the grid
    Sampling sampling = Sampling::grid; ///< how the points are drawn from the axes
    long samples = 0;                   ///< random / Latin hypercube: number of points
    unsigned long long seed = 1;        ///< random / Latin hypercube seed
    KeptResults keep; ///< the result columns written besides F_m and the parameters
    /// "attractors": starts per point for the design value F_m_max (attractors.hpp; the paper's
    /// uniform row only), 0 (off) .. 10000; the starts are seeded by the point's index.
    long attractor_starts = 0;
    std::string source; ///< file it came from
};

/// Number of points of the study.
long point_count(const Study& study);

/// The axis values of point `index` (0 <= index < point_count), deterministic.
std::vector<double> point_values(const Study& study, long index);

/// What one point runs: made from the study's base scene and the point's values by the scene
/// layer (study.hpp), so that the sweep itself knows nothing of scene files.
struct SweepPointInput {
    Dynamics dynamics;                          ///< the row and its ground motion
    RunOptions run;                             ///< the run
    std::vector<double> initial;                ///< initial state (empty: rest)
    ReducedParameters reduced;                  ///< the five reduced numbers
    std::optional<PhysicalParameters> physical; ///< set for physical scenes (F_m in newtons)
    bool uniform = true;  ///< the paper's homogeneous row with the linear law (regime needs it)
    bool harmonic = true; ///< harmonic forcing (regime needs a forcing period)
};

/// Makes the input of point `index`; throws std::invalid_argument (or SceneError) naming the
/// key of a bad value.
using SweepPointFactory = std::function<SweepPointInput(long index)>;

/// One finished point.
struct SweepPointResult {
    long index = 0;               ///< the point's index in the study, 0 .. points - 1 (its CSV row)
    std::vector<double> values;   ///< axis values
    ReducedParameters parameters; ///< the point's reduced parameters
    /// Harmonic forcing. A record or Kanai-Tajimi motion has none: parameters.f_r is then the
    /// reduced 1, not a forcing frequency, and the CSV's f_r cell is empty (Python: NaN)
    bool harmonic = true;
    SimulationResult simulation; ///< F_m and the rest
    /// The answer depends on the start: simulation.multistable, or with attractors > 0
    /// multistable(simulation, its design value) (design_value.hpp)
    bool multistable = false;
    std::optional<Classification> regime; ///< if the study keeps the regime
    std::optional<double> F_m_max;        ///< design value over the attractors (attractors > 0)
    double F_m_max_error = 0.0;           ///< its error (NaN where not estimated)
    int attractors_found = 0; ///< attractors found (attractors > 0), unsettled groups not counted
    int attractors_unsettled = 0;     ///< of them unsettled: F_m_max may be a transient's
    std::optional<double> F_m_newton; ///< F_m in newtons, for physical scenes
    /// F_m_error in newtons, for physical scenes where F_m_error was estimated [N, >= 0]
    std::optional<double> F_m_error_newton;
    /// F_m_max and F_m_max_error in newtons, for physical scenes with attractors > 0 [N]
    std::optional<double> F_m_max_newton;
    std::optional<double> F_m_max_error_newton; ///< see F_m_max_newton
};

/// Which points to run: a shard of the index range, minus those already done.
struct SweepSelection {
    int shard = 0;            ///< this shard, 0 <= shard < shards
    int shards = 1;           ///< points with index % shards == shard belong to it
    std::vector<long> subset; ///< if non-empty: only these indices (before sharding)
    std::vector<char> done;   ///< done[index] != 0: skip (resume)
    int threads = 0;          ///< OpenMP threads (0: all)
};

/// count indices of [0, total), one in each of count equal strata, drawn by a seeded hash of
/// the stratum (0 <= count <= total): a sample of a study that covers its whole index range.
std::vector<long> stratified_subset(long total, long count, std::uint64_t seed);

/// The indices selection would run, in index order.
std::vector<long> pending_points(const Study& study, const SweepSelection& selection);

/// How a sweep ended.
enum class SweepEnd {
    completed, ///< every pending point ran and reached the sink
    cancelled, ///< the progress callback stopped it; points not reported to the sink never ran
               ///< or were dropped
};

/// Runs the pending points in parallel (OpenMP, dynamic schedule) through the library's one
/// parallel loop; sink is called once per finished point, one call at a time, in completion
/// order. A point that fails numerically is reported through its result's status; a bad value
/// found at a point (or an exception of the sink) stops the sweep and is rethrown as itself.
SweepEnd run_sweep(const Study& study, const SweepSelection& selection,
                   const SweepPointFactory& make_point,
                   const std::function<void(const SweepPointResult&)>& sink,
                   const ProgressCallback& progress = {});

} // namespace gapchain
