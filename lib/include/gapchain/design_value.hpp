#pragma once
/// \file design_value.hpp
/// One run's F_m set against the attractors of its row (find_attractors()): the design value
/// F_m_max over both, whether the run's start reached a weaker attractor or a transient, and
/// where a non-periodic label read from one start stands among the search's groups.

#include "gapchain/attractors.hpp"
#include "gapchain/classify.hpp"
#include "gapchain/simulation.hpp"

#include <limits>
#include <string_view>

namespace gapchain {

/// One run's F_m set against the attractors of its row: the design value over both, and
/// whether another attractor hits harder than the run's start does.
struct DesignValue {
    AttractorSet search; ///< find_attractors() from the options' random starts
    /// The design value: the largest of the search's F_m_max and the run's F_m (a run whose
    /// transient outlasts its discarded periods counts: the row shaken from that start reaches
    /// it); the search's alone if the run failed or was stopped. NaN where neither gives one
    /// (the search cancelled, or every start failed and the run did not answer).
    double F_m_max = std::numeric_limits<double>::quiet_NaN();
    /// The error of whichever gave F_m_max; NaN if that is the run and its error was not
    /// estimated (run.estimate_error false), and where F_m_max is.
    double F_m_max_error = std::numeric_limits<double>::quiet_NaN();
    bool from_run = false; ///< F_m_max is the run's own F_m
    /// The search's F_m_max exceeds the run's F_m by more than 3 (F_m_error + F_m_max_error)
    /// and the accuracy asked (run.tolerance F_m_max): the run's start reached a weaker
    /// attractor, so its F_m is not the row's worst case. Only when the run answered (completed
    /// or steady state) and the search found a settled attractor.
    bool start_below = false;
    /// The run's F_m exceeds the search's F_m_max by as much: no attractor found reaches it, so
    /// the run's window held a transient (or, for a run that finished relaxed, motion of the
    /// relaxed plan that the strict dynamics leave). Same conditions. A run whose maximum fell
    /// before the orbit it settled on (SimulationResult::maximum_in_transient) has its F_m_error
    /// widened to cover that orbit's F_m, so it is not set: the run says so itself.
    bool run_above = false;
    ReducedParameters row;       ///< the row searched (its state scale, for label_in_search())
    double overlap_factor = 3.0; ///< the search's AttractorOptions::overlap_factor
};

/// What one run from one start answered, as design_value() sets it against the attractors:
/// a simulate() result, or a classification's F_m.
struct RunAnswer {
    bool answered = false; ///< the run completed or stopped at its steady state
    double F_m = 0.0;      ///< its largest reduced impact force, >= 0
    /// its error [reduced force, >= 0]; NaN where not estimated
    double F_m_error = std::numeric_limits<double>::quiet_NaN();
};

/// find_attractors(p, options) and the comparison with run, the answer of one run of row p
/// (from any start). Throws std::invalid_argument as find_attractors() does.
DesignValue design_value(const ReducedParameters& p, const AttractorOptions& options,
                         const RunAnswer& run, const ProgressCallback& progress = {});

/// design_value() of a simulate() result of row p under options.run.
DesignValue design_value(const ReducedParameters& p, const AttractorOptions& options,
                         const SimulationResult& run, const ProgressCallback& progress = {});

/// design_value() of a classification of row p (its F_m and F_m_error; answered where its run
/// completed or stopped at its steady state).
DesignValue design_value(const ReducedParameters& p, const AttractorOptions& options,
                         const Classification& classified, const ProgressCallback& progress = {});

/// Where a non-periodic label read from one start stands among the groups of an attractor
/// search of its row.
enum class LabelInSearch {
    not_applicable, ///< the label is periodic or no-contact (its state repeats: no question)
    /// a settled chaotic or quasi-periodic attractor of the search has the label's F_m
    attractor,
    /// only an unsettled group has it (a chaotic transient whose starts left it for orbits, or
    /// runs still converging): the label was read on a transient, as on Fig 13's row at
    /// f_r = 2.05 (a chaotic saddle) and 3.2 (the slow approach to the period-15 orbit)
    transient,
    /// no group has it: the search's starts did not reach the motion read (N starts miss a
    /// basin of fraction q with odds (1 - q)^N); no verdict
    not_reached,
};

/// "not_applicable", "attractor", "transient" or "not_reached".
std::string_view to_string(LabelInSearch where);

/// Where c's label stands among design's search. A non-periodic group has the label's motion
/// where their F_m differ by at most three times the sum of their errors, or 5 % of the larger
/// (the maximum of a chaotic record moves more than its error bar says from one sample to the
/// next), and, where c kept its section states (ClassifyOptions::keep_section_states), their
/// section points overlap as the search's own grouping tests them (two motions of one F_m are
/// not one).
LabelInSearch label_in_search(const Classification& c, const DesignValue& design);

/// Whether run's answer depends on its start: its own checks said so (run.multistable), or
/// another attractor hits harder (start_below), or none reaches its F_m (run_above).
bool multistable(const SimulationResult& run, const DesignValue& design);

} // namespace gapchain
