#pragma once
// What the attractor search (attractors.cpp) shares with the modules built on it: the design
// value (design_value.cpp) and the basin-fraction line (basin_fractions.cpp).

#include "gapchain/attractors.hpp"
#include "gapchain/dynamics.hpp"
#include "gapchain/model.hpp"

#include <optional>
#include <string>
#include <vector>

namespace gapchain::detail {

/// The row's natural scales: u in units of A, v in units of 2 pi f_r A.
struct StateScale {
    double u = 1.0;
    double v = 1.0;
    int Nm = 1;
    [[nodiscard]] double of(int i) const { return i < Nm ? u : v; }
};

/// The scales of row p (A of eq (20)).
StateScale state_scale(const ReducedParameters& p);

/// The row p is one an attractor search takes (beyond the model's own ranges), or why not.
std::optional<std::string> search_row_error(const ReducedParameters& p);

/// The two-sample nearest-neighbour test of attractors.hpp: whether the section clouds a and b
/// (states, scaled by scale) sample one attractor, at overlap factor `factor`.
bool clouds_overlap(const std::vector<std::vector<double>>& a,
                    const std::vector<std::vector<double>>& b, const StateScale& scale,
                    double factor);

/// The body-steps of a search of the row dyn under options, every start run to its full length
/// with what one non-periodic group adds (what run.max_work bounds).
double search_body_steps(const Dynamics& dyn, const AttractorOptions& options);

/// The attractor among `attractors` (by id) that a run from `state` reaches, or -1: the run of
/// one start of the search, grouped as the search groups its starts.
int attractor_reached_from(const Dynamics& dyn, const AttractorOptions& options,
                           const std::vector<double>& state,
                           const std::vector<Attractor>& attractors, const StateScale& scale,
                           const ProgressCallback& keep_going);

} // namespace gapchain::detail
