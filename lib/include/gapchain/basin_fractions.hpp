#pragma once
/// \file basin_fractions.hpp
/// Global continuation of basin fractions along one parameter, as Attractors.jl's: an attractor
/// search at each value, and each attractor followed from one value to the next.

#include "gapchain/attractors.hpp"
#include "gapchain/model.hpp"

#include <functional>
#include <vector>

namespace gapchain {

/// Basin fractions along one parameter: find_attractors() at each value, attractors matched
/// from one value to the next, so that a label follows an attractor across the line: first by
/// seeding (a run at the new value from a state on each previous attractor; the attractor it
/// reaches takes that label, the one nearest in F_m if several seeds reach it), then the
/// unmatched by the nearest centroid of the section points within 0.2 A; never across a jump of
/// F_m by more than 25 % (F_m is continuous along an attractor that persists).
struct FractionContinuation {
    SweptParameter parameter = SweptParameter::f_r; ///< the parameter varied
    std::vector<double> values;                     ///< its values, in the parameter's units
    std::vector<AttractorSet> sets;                 ///< per value
    std::vector<std::vector<int>> labels;           ///< per value, per attractor: its global label
    int label_count = 0;                            ///< global labels used
    double wall_time_s = 0.0;                       ///< [s]
    bool cancelled = false;
};

/// The values of a basin-fraction line: steps values from `from` to `to`, both included, as
/// from + (to - from) k / (steps - 1) (one value needs from = to, and from = to one value).
/// Throws std::invalid_argument naming from or to when an end is outside `parameter`'s range
/// for base, or steps outside 1 .. 10000.
std::vector<double> fraction_line_values(const ReducedParameters& base, SweptParameter parameter,
                                         double from, double to, int steps);

/// Called once a value of a basin-fraction line is done, with the line so far (its last
/// value, set and labels are the new ones). What it reported stays in the line: a line
/// cancelled later returns every value done before (cancelled set).
using FractionValueCallback = std::function<void(const FractionContinuation& line)>;

/// find_attractors() at every value of `parameter` (each set in parallel over its starts).
FractionContinuation continue_basin_fractions(const ReducedParameters& base,
                                              SweptParameter parameter,
                                              const std::vector<double>& values,
                                              const AttractorOptions& options,
                                              const ProgressCallback& progress = {},
                                              const FractionValueCallback& on_value = {});

} // namespace gapchain
