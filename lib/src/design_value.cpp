#include "gapchain/design_value.hpp"

#include "detail/attractor_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gapchain {

using detail::clouds_overlap;
using detail::state_scale;
using detail::StateScale;

DesignValue design_value(const ReducedParameters& p, const AttractorOptions& options,
                         const SimulationResult& run, const ProgressCallback& progress) {
    RunAnswer answer;
    answer.answered = run.status == RunStatus::completed || run.status == RunStatus::steady_state;
    answer.F_m = run.F_m;
    if (has_error_estimate(run)) answer.F_m_error = run.F_m_error;
    return design_value(p, options, answer, progress);
}

DesignValue design_value(const ReducedParameters& p, const AttractorOptions& options,
                         const Classification& classified, const ProgressCallback& progress) {
    RunAnswer answer;
    answer.answered =
        classified.status == RunStatus::completed || classified.status == RunStatus::steady_state;
    answer.F_m = classified.F_m;
    answer.F_m_error = classified.F_m_error;
    return design_value(p, options, answer, progress);
}

DesignValue design_value(const ReducedParameters& p, const AttractorOptions& options,
                         const RunAnswer& run, const ProgressCallback& progress) {
    DesignValue d;
    d.row = p;
    d.overlap_factor = options.overlap_factor;
    d.search = find_attractors(p, options, progress);
    if (d.search.cancelled) return d;
    // A search with no group (every start failed) has no F_m: NaN, where 0 +- 0 read as a
    // design value (a reread, helper-86).
    const bool any_group = d.search.F_m_max_id >= 0;
    const double none = std::numeric_limits<double>::quiet_NaN();
    d.F_m_max = any_group ? d.search.F_m_max : none;
    d.F_m_max_error = any_group ? d.search.F_m_max_error : none;
    // A run that failed or was stopped has no F_m to set against the attractors; a search
    // whose groups were all still converging has no attractor's F_m to set it against.
    const bool attractor_found = any_group && d.search.any_settled();
    if (!run.answered) return d;
    const double run_error = run.F_m_error;
    // Where every group was still converging, the search's F_m_max is a transient's; the larger
    // of it and the run's stands all the same, and from_run says which (it once said "the run's"
    // whenever nothing settled, next to the group's larger F_m).
    d.from_run = !any_group || run.F_m >= d.search.F_m_max;
    if (d.from_run) {
        d.F_m_max = run.F_m;
        d.F_m_max_error = run_error;
    }
    if (!attractor_found) return d;
    const double gap = d.search.F_m_max - run.F_m;
    const double errors =
        std::isnan(run_error) ? d.search.F_m_max_error : run_error + d.search.F_m_max_error;
    const double allowance =
        std::max(3.0 * errors, options.run.tolerance * std::max(run.F_m, d.search.F_m_max));
    d.start_below = gap > allowance;
    d.run_above = -gap > allowance;
    return d;
}

bool multistable(const SimulationResult& run, const DesignValue& design) {
    return run.multistable || design.start_below || design.run_above;
}

std::string_view to_string(LabelInSearch where) {
    switch (where) {
    case LabelInSearch::not_applicable: return "not_applicable";
    case LabelInSearch::attractor: return "attractor";
    case LabelInSearch::transient: return "transient";
    case LabelInSearch::not_reached: return "not_reached";
    }
    return "not_applicable";
}

LabelInSearch label_in_search(const Classification& c, const DesignValue& design) {
    if (c.regime != Regime::chaotic && c.regime != Regime::quasi_periodic)
        return LabelInSearch::not_applicable;
    // Matched by motion, not by label: the search calls a group unsettled for reasons the
    // classification does not weigh (members that left for orbits, an exponent still negative).
    const auto same_force = [&c](const Attractor& a) {
        const double bar = 3.0 * (c.F_m_error + a.F_m_error);
        return std::abs(c.F_m - a.F_m) <= std::max(bar, 0.05 * std::max(c.F_m, a.F_m));
    };
    const StateScale scale = state_scale(design.row);
    const auto same_set = [&](const Attractor& a) {
        return c.section_states.empty() || a.section.empty() ||
               clouds_overlap(c.section_states, a.section, scale, design.overlap_factor);
    };
    bool unsettled_match = false;
    for (const Attractor& a : design.search.attractors) {
        if (a.period != 0 || !same_force(a) || !same_set(a)) continue;
        if (a.settled) return LabelInSearch::attractor;
        unsettled_match = true;
    }
    return unsettled_match ? LabelInSearch::transient : LabelInSearch::not_reached;
}

} // namespace gapchain
