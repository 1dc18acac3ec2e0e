#pragma once
/// \file continuation.hpp
/// Pseudo-arclength continuation of the row's periodic orbits in one reduced parameter, through
/// folds, with the special points located on the way: fold (a Floquet multiplier through +1),
/// period doubling (through -1), Neimark-Sacker (a complex pair through the unit circle) and
/// grazing (a contact's largest gap along the orbit through 0: the orbit's contact set changes).
/// Optionally each period doubling switches to the doubled branch and follows it.

#include "gapchain/model.hpp"
#include "gapchain/orbit.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace gapchain {

/// Kinds of special points.
enum class SpecialPointType {
    /// The branch turns back in the parameter, a multiplier crossing +1 (or, at a grazing
    /// corner, multipliers jumping across the unit circle): no orbit near the turn goes on
    /// past it
    fold,
    period_doubling, ///< a multiplier -1
    neimark_sacker,  ///< a complex pair crosses the unit circle
    grazing,         ///< a contact's closings per orbit change
    /// A multiplier +1 where another branch meets this one: this branch goes on through it,
    /// or turns there (a branch born at a pitchfork of a mirror-symmetric orbit, into its own
    /// mirror image or onto the symmetric orbit): an orbit near the turn goes on past it
    branch_point,
};

/// Name of a kind, as written in results ("fold", "period_doubling", ...).
std::string_view to_string(SpecialPointType type);

/// What to continue and how.
struct ContinuationOptions {
    SweptParameter parameter = SweptParameter::f_r; ///< the continued reduced number
    double from = 2.15;     ///< start value (the first orbit is found there)
    double to = 4.5;        ///< end value: the branch's last point lands on it (Newton at this
                            ///< value), or lies past it where that fails
    int period = 1;         ///< k of the first branch [forcing periods], 1 .. 1000
    double step = 0.01;     ///< first arclength step, [1e-6, 1]
    double max_step = 0.05; ///< largest arclength step, [step, 1]
    int max_points = 2000;  ///< points per branch, 1 .. 1e6
    /// switch to the doubled branch at each period doubling, and at each non-smooth loss of
    /// stability next to -1 (a multiplier jumping across the unit circle within 10 degrees of -1)
    bool follow_doublings = false;
    /// Branches followed in all, 1 .. 64: restarts beyond a point where a branch ended, and
    /// with follow_doublings the doubled branches.
    int max_branches = 6;
    double locate_tolerance = 1e-6; ///< special points located to this in the parameter
    long transient_periods = 200;   ///< plain run before the first Newton search, 0 .. 1e7
    OrbitOptions orbit;             ///< Newton and integration settings (its period is set here)
};

/// One continued orbit.
struct BranchPoint {
    double value = 0.0; ///< the parameter
    int period = 1;     ///< k of the branch
    double F_m = 0.0;   ///< largest reduced impact force over the orbit
    /// Error of F_m [reduced force, >= 0]: orbit_force_error() (the difference from the same
    /// orbit on an independent scheme); NaN where that check would exceed max_work or failed
    double F_m_error = 0.0;
    double u1 = 0.0;             ///< u_1 at phase 0
    bool stable = false;         ///< every Floquet multiplier inside the unit circle
    double max_multiplier = 0.0; ///< largest modulus
    int branch = 0;              ///< branch index (0: the first)
    /// The orbit's minimal period, a divisor of period (a period-1 orbit continued as period 2
    /// has 1: there a multiplier -1 of its own map shows as +1, a branch point of the 2-map)
    int minimal_period = 1;
    /// The orbit's state at phase 0 (u_1..u_Nm, v_1..v_Nm): a start for gapchain-orbit, a run
    /// or another continuation.
    std::vector<double> state;
};

/// A located special point.
struct SpecialPoint {
    SpecialPointType type = SpecialPointType::fold;
    double value = 0.0; ///< the parameter
    /// The special point lies within value_error of `value` (the width of the final bracket,
    /// whose one end is the reported orbit; for a fold, which lies past both ends, also twice
    /// how far the branch turns beyond them, and at least the orbit tolerance times
    /// (1 + |value|)): <= locate_tolerance when located.
    double value_error = 0.0;
    int period = 1;         ///< k of the branch it lies on
    int minimal_period = 1; ///< the orbit's minimal period there (see BranchPoint)
    double F_m = 0.0;       ///< F_m of the orbit there
    /// its error [reduced force]: BranchPoint::F_m_error's, or the difference between the F_m
    /// of the final bracket's two ends where that is larger
    double F_m_error = 0.0;
    int branch = 0;   ///< branch index
    int contact = -1; ///< the contact j = 0..Nm of a grazing, else -1
};

/// Branches and special points.
struct ContinuationResult {
    std::vector<BranchPoint> points; ///< in the order computed, branch by branch
    /// In the order found; one a branch finds again (same type and contact, the intervals
    /// value +- value_error overlapping, as where a step crosses a branch point onto the other
    /// branch there) is listed once, its interval and F_m_error covering both
    std::vector<SpecialPoint> special;
    std::vector<std::string> branch_end; ///< per branch, why it ended
    /// Branches found (a doubling's, a restart's) and not traced because max_branches was
    /// reached: where each would have started ("period 2 from f_r = 2.25398")
    std::vector<std::string> unfollowed;
    long shootings = 0;       ///< k-period integrations with the tangent flow
    bool cancelled = false;   ///< the progress callback asked to stop
    double wall_time_s = 0.0; ///< [s]
};

/// How well the F_m of a continuation's orbits and special points are known.
struct ForceErrorSummary {
    double largest = 0.0; ///< largest F_m_error among those estimated [reduced force, >= 0]
    long unestimated = 0; ///< orbits and special points whose F_m_error is NaN (not estimated)
    long orbits = 0;      ///< orbits and special points in all
};

/// The F_m errors of result's points and special points, summed up.
ForceErrorSummary force_error_summary(const ContinuationResult& result);

/// Throws std::invalid_argument naming the first option outside its range.
void validate(const ContinuationOptions& options);

/// Continues the periodic orbit of the paper's uniform row base (its swept parameter replaced
/// by options.from) found after options.transient_periods from initial (empty: rest). Throws
/// std::invalid_argument on bad options, and naming run.max_work where one shooting, or the
/// walk (max_branches branches of min(max_points, |to - from| / max_step) points of three
/// shootings), would exceed options.orbit.max_work; numerical endings are in branch_end.
ContinuationResult continue_orbits(const ReducedParameters& base,
                                   const ContinuationOptions& options,
                                   const std::vector<double>& initial = {},
                                   const ProgressCallback& progress = {});

} // namespace gapchain
