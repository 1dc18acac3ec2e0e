#include "gapchain/bifurcation.hpp"

#include "detail/check.hpp"
#include "detail/parallel.hpp"
#include "gapchain/grid.hpp"
#include "gapchain/observers.hpp"
#include "gapchain/orbit.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace gapchain {

SweepMode parse_sweep_mode(std::string_view name) {
    if (name == "independent") return SweepMode::independent;
    if (name == "continuation") return SweepMode::continuation;
    throw std::invalid_argument("mode: must be independent or continuation, got \"" +
                                std::string(name) + "\"");
}

std::string_view to_string(SweepDirection d) {
    return d == SweepDirection::up ? "up" : "down";
}

namespace {

/// The section of a diagram's runs and the indices of its plotted variables in it.
struct PlottedSection {
    SectionSpec spec;
    std::vector<std::size_t> plotted;
};

/// o's section recording the whole state first (u_1..u_Nm, v_1..v_Nm), then any plotted
/// variable that is not part of it, with each plotted variable's index. The period is the
/// state's, not the plotted variable's: a contact force is 0 at every section time where the
/// contact is open (F0 read "period 1" on chaotic rows), and t never repeats.
PlottedSection state_section(const SectionSpec& o, int Nm) {
    PlottedSection section{o, {}};
    std::vector<SectionVariable>& record = section.spec.record;
    record = SectionVariable::whole_state(Nm);
    for (const auto& v : o.record) {
        const auto same = [&v](const SectionVariable& w) {
            return w.kind == v.kind && w.index == v.index;
        };
        const auto at = std::find_if(record.begin(), record.end(), same);
        section.plotted.push_back(static_cast<std::size_t>(at - record.begin()));
        if (at == record.end()) record.push_back(v);
    }
    return section;
}

/// The plotted values of a point of the state section, its time moved by t_shift.
SectionPoint plotted_point(const SectionPoint& s, const PlottedSection& section, double t_shift) {
    SectionPoint kept{s.t + t_shift, {}};
    for (const std::size_t k : section.plotted)
        kept.values.push_back(s.values[k]);
    return kept;
}

/// One cycle of a confirmed orbit's section points, from its phase-0 state on the exact scheme
/// (on which Newton converged), the times moved by t_shift.
std::vector<SectionPoint> orbit_section_points(const Dynamics& dyn, const PeriodicOrbit& orbit,
                                               const PlottedSection& section, double t_shift) {
    RunOptions options;
    options.periods = orbit.minimal_period;
    options.transient_periods = 0;
    options.scheme = Scheme::exact;
    PlannedRun cycle(dyn, options, orbit.state);
    std::vector<SectionPoint> points;
    PoincareSampler sampler(dyn, section.spec, [&](const SectionPoint& s) {
        points.push_back(plotted_point(s, section, t_shift));
    });
    Observer* observers[] = {&sampler};
    cycle.run(observers);
    return points;
}

/// A periodic row's orbit, confirmed by Newton on the exact scheme from the run's end state (a
/// period boundary). Its F_m carries none of the row's scheme's truncation error, which
/// tolerance * F_m does not bound: on Fig 13's row rk4 at the default tolerance read 0.00363071
/// +- 3.6e-7 at f_r = 4.119, where the orbit's is 0.00365717 (the contact barely closes, and a
/// small penetration is the difference of two displacements each held to the tolerance), and
/// 0.587975 +- 5.9e-5 at 2.47 against 0.588247. Its minimal period is the exact dynamics': at
/// 4.1092 rk4 settles on a period-4 orbit of its own (a spurious doubling), the exact orbit has
/// period 2.
void confirm_row_orbit(const Dynamics& dyn, const std::vector<double>& end_state, double t_end,
                       const BifurcationOptions& o, const PlottedSection& section,
                       BifurcationRow& row) {
    const auto found = confirm_periodic_orbit(dyn, row.period, end_state, o.max_work);
    if (!found || found->status != OrbitStatus::converged) return;
    row.newton_confirmed = true;
    // The window's points are then a cycle of the row's scheme that the exact dynamics do not
    // have (rk4's four points at 4.1092, about an orbit of two): the diagram draws the orbit's,
    // as the row reports its period, over the run's last cycle.
    if (found->minimal_period < row.period) {
        row.points = orbit_section_points(dyn, *found, section,
                                          t_end - found->minimal_period * dyn.period());
        row.points_from_orbit = true;
    }
    row.period = found->minimal_period;
    row.max_multiplier = found->max_multiplier;
    // As classify() reports it: the orbit's F_m, with a bar that covers the recorded one, and
    // at least the tolerance of the orbit's own F_m.
    row.F_m_error =
        std::max({row.F_m_error, std::abs(row.F_m - found->F_m), o.tolerance * found->F_m});
    row.F_m = found->F_m;
}

/// The maximum over the row's window run from the same start on a finer plan (twice the steps
/// of a fixed-step scheme, a hundredth of an adaptive scheme's tolerance and half its output
/// interval); nothing where that run alone exceeds max_work (a single row of more than half of
/// it is not run, rather than fail the diagram after its runs) or did not complete. A
/// cancelled comparison cancels the row.
std::optional<double> finer_window_maximum(const Dynamics& dyn, const RunOptions& options,
                                           const StepPlan& plan, const std::vector<double>& start,
                                           const ProgressCallback& keep_going,
                                           BifurcationRow& row) {
    const StepPlan finer = finer_plan(dyn, plan, 100.0);
    if (run_work(dyn, finer, static_cast<double>(options.periods)) > options.max_work)
        return std::nullopt;
    PlannedRun comparison(dyn, options, finer, start);
    MaxForceTracker forces(dyn);
    Observer* observers[] = {&forces};
    const RunStatus status = comparison.run(observers, keep_going).status;
    if (status == RunStatus::cancelled) row.status = status;
    if (status != RunStatus::completed) return std::nullopt;
    return forces.max_force();
}

/// A periodic row Newton did not confirm, and a row that is not periodic, keeps its window's
/// F_m; its bar covers twice the difference from the finer window: rk4's period-5 cell at
/// f_r = 2.1253 on Fig 13's row read 1.140344 +- 1.1e-4, where the exact scheme never settles
/// and reads 1.142547.
void bound_by_finer_run(const Dynamics& dyn, const RunOptions& options, const StepPlan& plan,
                        const std::vector<double>& start, const ProgressCallback& keep_going,
                        BifurcationRow& row) {
    if (const auto finer = finer_window_maximum(dyn, options, plan, start, keep_going, row))
        row.F_m_error = std::max(row.F_m_error, 2.0 * std::abs(row.F_m - *finer));
}

/// A confirmed orbit is the exact dynamics' own, but whether the start reaches it can hang on
/// the scheme's error where the start lies near a basin boundary (a researcher's probe,
/// helper-81: Nm 3, fc 100, eps 0.2, e_r 0.1 from rest, rk4 at 1e-4 read
/// 1.69577 +- 1.7e-4 at f_r = 3.45 and 0 +- 0 at 3.49, where the exact scheme and an
/// independent integrator read 0 and 1.74245). The finer window tells: far from the orbit's F_m
/// (beyond ten times the bar and 1e-3 of the larger), it settled elsewhere, and the bar covers
/// twice the difference. Near it, the bar stands: the finer window's own truncation error is no
/// error of the orbit's F_m.
void check_finer_run_reaches_orbit(const Dynamics& dyn, const RunOptions& options,
                                   const StepPlan& plan, const std::vector<double>& start,
                                   const ProgressCallback& keep_going, BifurcationRow& row) {
    const auto finer = finer_window_maximum(dyn, options, plan, start, keep_going, row);
    if (!finer) return;
    const double difference = std::abs(row.F_m - *finer);
    if (difference <= std::max(10.0 * row.F_m_error, 1e-3 * std::max(row.F_m, *finer))) return;
    row.ended_elsewhere = true;
    row.F_m_error = std::max(row.F_m_error, 2.0 * difference);
}

/// One value: run transient + record periods from y (empty: rest; updated to the end state);
/// keep_going may stop it (status cancelled).
BifurcationRow diagram_row(const ReducedParameters& p, const BifurcationOptions& o,
                           std::vector<double>& y, SweepDirection direction, double value,
                           const ProgressCallback& keep_going) {
    const Dynamics dyn = Dynamics::paper_row(p);
    RunOptions options;
    options.periods = o.transient_periods + o.record_periods;
    options.transient_periods = o.transient_periods;
    options.scheme = o.scheme;
    options.tolerance = o.tolerance;
    options.max_work = o.max_work;
    const std::vector<double> start = y;
    PlannedRun planned(dyn, options, y);
    BifurcationRow row;
    row.value = value;
    row.direction = direction;
    row.points.reserve(static_cast<std::size_t>(o.record_periods));
    const PlottedSection section = state_section(o.section, p.Nm);
    const auto state_size = static_cast<std::ptrdiff_t>(2 * p.Nm);
    SectionRepeats repeats(o.max_period);
    PoincareSampler sampler(dyn, section.spec, [&](const SectionPoint& s) {
        repeats.add({s.values.begin(), s.values.begin() + state_size});
        row.points.push_back(plotted_point(s, section, 0.0));
    });
    // Split at the middle of the recorded periods: the halves' maxima give the sampling spread.
    const long split = o.record_periods >= 2 ? o.transient_periods + o.record_periods / 2 : -1;
    MaxForceTracker forces(dyn, split);
    Observer* observers[] = {&sampler, &forces};
    const RunOutcome outcome = planned.run(observers, keep_going);
    row.status = outcome.status;
    y = planned.state();
    row.F_m = forces.max_force();
    // A cycle's points must be distinct, or the row is closing in on an orbit of the shorter
    // period (Newton, where it runs, starts from the period read here).
    row.period = repeats.period(o.period_tolerance, true);
    row.F_m_error = forces.window_error(o.tolerance, row.period > 0);
    if (o.confirm_by_newton && row.period > 0 && row.status == RunStatus::completed) {
        confirm_row_orbit(dyn, y, outcome.t_end, o, section, row);
        if (row.newton_confirmed)
            check_finer_run_reaches_orbit(dyn, options, planned.plan(), start, keep_going, row);
        else
            bound_by_finer_run(dyn, options, planned.plan(), start, keep_going, row);
    }
    // A row that is not periodic has no orbit to confirm: its window's maximum is a sample
    // (of a chaos, a torus, or a transient still going), and only a second sample on a finer
    // plan says how far it can move. Without it the bar was the halves' spread and the
    // tolerance: Fig 13's row at f_r = 2.6 (100 discarded, 1 recorded) read 0.364675 +- 3.6e-5,
    // where the exact scheme and rk8pd agree on 0.379490 (400 bars off).
    if (row.period == 0 && row.status == RunStatus::completed)
        bound_by_finer_run(dyn, options, planned.plan(), start, keep_going, row);
    return row;
}

/// Independent mode: each value from the initial state, in parallel, into its own slot.
void independent_rows(const ReducedParameters& base, const BifurcationOptions& o,
                      const ProgressCallback& progress, BifurcationResult& result) {
    const std::vector<double> values = linspace(o.from, o.to, o.steps);
    result.rows.resize(values.size());
    for (std::size_t k = 0; k < values.size(); ++k) {
        result.rows[k].value = values[k];
        result.rows[k].status = RunStatus::cancelled;
    }
    result.threads_used = detail::thread_count(o.threads);
    detail::SharedProgress shared(progress, o.steps);
    const auto end = detail::parallel_for(
        o.steps, result.threads_used,
        [&](long k) {
            std::vector<double> y = o.initial; // empty: rest (PlannedRun)
            // No value starts from another's end: the label only says which way the line goes.
            const SweepDirection dir = o.from <= o.to ? SweepDirection::up : SweepDirection::down;
            BifurcationRow row = diagram_row(with_value(base, o.parameter, values[k]), o, y, dir,
                                             values[k], shared.item_callback());
            // A row stopped part-way holds part of its points and maxima: none is kept.
            if (row.status != RunStatus::cancelled) result.rows[k] = std::move(row);
        },
        [&](long) { return shared.finished(); });
    result.cancelled = end == detail::LoopEnd::cancelled;
}

/// Continuation mode: from `from` to `to` and back, each value from the previous end state.
void continued_rows(const ReducedParameters& base, const BifurcationOptions& o,
                    const ProgressCallback& progress, BifurcationResult& result) {
    const std::vector<double> values = linspace(o.from, o.to, o.steps);
    std::vector<double> y = o.initial; // empty: rest (PlannedRun)
    const int total = 2 * o.steps;
    int done = 0;
    const ProgressCallback keep_going = [&](double) {
        return !progress || progress(static_cast<double>(done) / total);
    };
    // From `from` to `to` and back; a leg is labelled by whether the value grows along it, so
    // that a line given from 4 down to 2 labels its first leg down.
    const bool rising = o.from <= o.to;
    for (const bool outward : {true, false}) {
        const SweepDirection dir = outward == rising ? SweepDirection::up : SweepDirection::down;
        for (int i = 0; i < o.steps; ++i) {
            const int k = outward ? i : o.steps - 1 - i;
            result.rows.push_back(diagram_row(with_value(base, o.parameter, values[k]), o, y, dir,
                                              values[k], keep_going));
            if (result.rows.back().status == RunStatus::cancelled) {
                result.rows.pop_back();
                result.cancelled = true;
                return;
            }
            // A run that blew up cannot seed the next value: restart that one from the start.
            if (result.rows.back().status == RunStatus::non_finite) y = o.initial;
            if (progress && !progress(static_cast<double>(++done) / total)) {
                result.cancelled = true;
                return;
            }
        }
    }
}

/// run.max_work against the whole diagram, at the costlier end's steps.
void require_diagram_affordable(const BifurcationOptions& o, const ReducedParameters& base) {
    // The scheme must take both ends (exact's limit on the contacts' speed rises with fc): a
    // line that crossed it was refused only where it got there, its output lost.
    // run.max_work bounds the whole diagram, as it bounds an attractor search: each value's run
    // alone was checked, and 1e5 values of 1e4 periods (a day of work) were accepted. A value's
    // steps per period are largest at an end of the line (they fall with f_r, rise with fc).
    // Each row also runs its window on a finer plan (a confirmed orbit's check, or an
    // unconfirmed or non-periodic row's bar), counted with it.
    const double periods = static_cast<double>(o.transient_periods + o.record_periods);
    double per_value = 0.0;
    int steps_per_period = 0, finer_steps_per_period = 0;
    for (const double end : {o.from, o.to}) {
        const Dynamics dyn = Dynamics::paper_row(with_value(base, o.parameter, end));
        const StepPlan plan = plan_step(dyn, o.scheme, o.tolerance);
        const StepPlan finer = finer_plan(dyn, plan, 100.0);
        const double work = run_work(dyn, plan, periods) + run_work(dyn, finer, periods);
        if (work > per_value) {
            per_value = work;
            steps_per_period = plan.steps_per_period;
            finer_steps_per_period = finer.steps_per_period;
        }
    }
    const long runs = o.steps * (o.mode == SweepMode::continuation ? 2L : 1L);
    detail::require_work(static_cast<double>(runs) * per_value, o.max_work,
                         "this diagram runs up to",
                         detail::format_number(static_cast<double>(runs)) + " runs x Nm " +
                             std::to_string(base.Nm) + " x (" + std::to_string(steps_per_period) +
                             " + " + std::to_string(finer_steps_per_period) +
                             " on the finer plan) steps per forcing period x " +
                             detail::format_number(periods) + " periods",
                         "fewer values, fewer periods, or raise run.max_work");
}

} // namespace

void validate(const BifurcationOptions& o, const ReducedParameters& base) {
    detail::require_range("steps", o.steps, 1, 10'000'000);
    require_line(o.from, o.to, o.steps);
    detail::require_count("transient_periods", o.transient_periods, 0, 1'000'000'000);
    detail::require_count("record_periods", o.record_periods, 1, 1'000'000'000);
    detail::require_run_length(o.transient_periods, o.record_periods);
    detail::require_range("max_period", o.max_period, 1, 1000);
    detail::require_range("period_tolerance", o.period_tolerance, 0.0, 1.0,
                          detail::Bound::open_low);
    detail::require_range("threads", o.threads, 0, 4096);
    detail::require_range("tolerance", o.tolerance, 1e-12, 0.1);
    detail::require_range("max_work", o.max_work, 1.0, 1e15);
    // The section's own time was accepted and plotted as a diagram of section times.
    for (const SectionVariable& v : o.section.record)
        (void)SectionVariable::parse_state(v.name(), base.Nm, "variable");
    // Every section point is kept until the diagram is written (~64 bytes each with its values):
    // refuse up front what would end in bad_alloc hours later. A stroboscopic section keeps one
    // per recorded period; an event section may keep more, which this does not foresee.
    const double kept = static_cast<double>(o.steps) * static_cast<double>(o.record_periods) *
                        (o.mode == SweepMode::continuation ? 2.0 : 1.0);
    if (kept > 1e8)
        throw std::invalid_argument(
            "record_periods: values x recorded periods = " + detail::format_number(kept) +
            " section points to keep (about " + detail::format_number(std::ceil(kept * 64e-9)) +
            " GB); at most 1e8: fewer values or fewer recorded periods");
    // Both ends must make a valid row: the model's message names the parameter and its range.
    if (const auto error = swept_value_error(base, o.parameter, o.from))
        throw std::invalid_argument("from: " + *error);
    if (const auto error = swept_value_error(base, o.parameter, o.to))
        throw std::invalid_argument("to: " + *error);
    (void)initial_state(Dynamics::paper_row(with_value(base, o.parameter, o.from)), o.initial);
    require_diagram_affordable(o, base);
    validate(o.section, base.Nm);
}

BifurcationResult bifurcation(const ReducedParameters& base, const BifurcationOptions& o,
                              const ProgressCallback& progress) {
    const auto start = std::chrono::steady_clock::now();
    validate(o, base);
    BifurcationResult result;
    if (o.mode == SweepMode::independent)
        independent_rows(base, o, progress, result);
    else
        continued_rows(base, o, progress, result);
    result.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

} // namespace gapchain
