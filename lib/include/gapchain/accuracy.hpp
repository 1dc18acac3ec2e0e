#pragma once
/// \file accuracy.hpp
/// Work-precision study: every scheme over a ladder of tolerances, its error against the exact
/// propagator at its tightest, its run time and its right-hand-side evaluations (error measures
/// as SciMLBenchmarks define them: final-time error, and L2 over once-per-period samples).

#include "gapchain/dynamics.hpp"
#include "gapchain/run.hpp"
#include "gapchain/stepper.hpp"

#include <optional>
#include <vector>

namespace gapchain {

/// What to measure.
struct WorkPrecisionOptions {
    std::vector<Scheme> schemes{Scheme::central_difference, Scheme::rk4, Scheme::rkf45,
                                Scheme::rk8pd, Scheme::exact};                ///< concrete schemes
    std::vector<double> tolerances{1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8}; ///< [1e-12, 0.1]
    long periods = 50;       ///< forcing periods per run (full length, no steady-state stop)
    int repeats = 3;         ///< timed repeats per point (the median is kept), 1 .. 100
    bool unsplit_too = true; ///< also run central_difference and rk4 (those of schemes) without
                             ///< switch splitting
    /// Body-steps the whole study may take (run.max_work), [1, 1e15]: its runs, repeats and
    /// reference together, each Nm x steps per period x periods.
    double max_work = 3e10;
};

/// The schemes the study also runs without switch splitting: central_difference and rk4, those
/// of options.schemes, when options.unsplit_too; else none.
std::vector<Scheme> unsplit_schemes(const WorkPrecisionOptions& options);

/// One run of the study.
struct WorkPrecisionPoint {
    Scheme scheme = Scheme::rk4; ///< the integrator of this run
    bool split = true;           ///< steps ended on contact switches
    double tolerance = 0.0;      ///< requested relative F_m tolerance
    double step = 0.0;           ///< step or output interval
    double F_m = 0.0;            ///< the run's F_m (reduced force, eq 19)
    double F_m_error = 0.0;      ///< relative, not absolute: |F_m - F_m,ref| / F_m,ref
    double final_error = 0.0;    ///< max-norm state error at the final time
    double l2_error = 0.0;       ///< RMS over once-per-period samples of the max-norm error
    double wall_time_s = 0.0;    ///< median over the repeats [s]
    long evaluations = 0;        ///< right-hand-side evaluations (exact: propagations)
};

/// The study.
struct WorkPrecision {
    double F_m_reference = 0.0; ///< exact propagator, half its default interval
    /// F_m_reference's error: the exact scheme's round-off floor, exact_F_m_round_off of it
    /// (stepper.hpp); the rows' F_m errors below it are not resolved
    double F_m_reference_error = 0.0;
    std::vector<WorkPrecisionPoint> points; ///< scheme-major, tolerance order
    double wall_time_s = 0.0;               ///< [s]
    bool cancelled = false; ///< progress stopped it: points holds the runs finished before
};

/// Runs the study on dyn from rest. Throws std::invalid_argument on bad options. progress
/// reports the fraction of the study's runs done; answering false stops it (cancelled).
WorkPrecision work_precision(const Dynamics& dyn, const WorkPrecisionOptions& options,
                             const ProgressCallback& progress = {});

/// The fastest point (any scheme, split steps) whose relative F_m error is at most target.
std::optional<WorkPrecisionPoint> fastest_for(const WorkPrecision& study, double target);

/// Least-squares slope of log F_m error against log step for one scheme's points with errors
/// above exact_F_m_round_off (stepper.hpp; the observed order); nullopt with fewer than 3 such
/// points.
std::optional<double> observed_order(const WorkPrecision& study, Scheme scheme, bool split);

} // namespace gapchain
