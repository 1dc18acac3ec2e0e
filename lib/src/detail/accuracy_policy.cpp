#include "detail/accuracy_policy.hpp"

#include "gapchain/observers.hpp"
#include "gapchain/stepper.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <span>

namespace gapchain::detail {

namespace {

/// The observers every run of simulate() feeds, set up from the options.
class RunWatch {
public:
    RunWatch(const Dynamics& dyn, const RunOptions& options, const TrajectorySink& trajectory,
             int every, const std::vector<Observer*>& extra)
        : m_forces(dyn,
                   options.transient_periods + (options.periods - options.transient_periods) / 2) {
        m_list.push_back(&m_forces);
        // A record has no period, so no periodic steady state: it runs to its end.
        if (options.stop_at_steady_state && dyn.ground_motion().is_harmonic()) {
            m_steady.emplace(dyn.dimension(), options.max_steady_period, options.steady_tolerance,
                             options.transient_periods, natural_angular_frequency);
            m_list.push_back(&*m_steady);
            m_list.push_back(&m_distances);
        }
        if (trajectory) {
            m_recorder.emplace(every, trajectory);
            m_list.push_back(&*m_recorder);
        }
        m_list.insert(m_list.end(), extra.begin(), extra.end());
    }
    RunWatch(const RunWatch&) = delete;
    RunWatch& operator=(const RunWatch&) = delete;

    [[nodiscard]] std::span<Observer* const> observers() const { return m_list; }
    /// Whether the run, at its last period boundary, has found no steady state, is far from one
    /// (farther than SteadyStateDetector::far_distance, 1e-3, from every cycle of up to
    /// max_steady_period periods; a run that decays onto a stable orbit at the contact-free rate
    /// is within 1e-12 of it by relaxation_period(), four times its decay time to 1e-3), and is
    /// not approaching one (that distance did not fall a thousandfold over the last
    /// approach_periods periods, as it does on the way to an orbit that attracts slowly; a
    /// chaotic run's distance wanders within a factor of ten or so). Measured on the paper-scale
    /// sample: a looser rule (1e-6, no approach test) relaxed slowly settling periodic points,
    /// which were then redone strict and cost 1.5x in all.
    [[nodiscard]] bool wandering() const {
        return m_steady && !m_steady->period() &&
               m_steady->nearest_cycle_distance() > SteadyStateDetector::far_distance &&
               m_distances.steady_wandering();
    }
    /// The observers, with one that stops the run as soon as it comes within wander_distance
    /// (1e-6) of a cycle: a relaxed run that does that is settling, and will be redone strict,
    /// so the rest of its relaxed periods would be wasted.
    [[nodiscard]] std::span<Observer* const> observers_stopping_near_a_cycle() {
        m_distances.stop_when_near();
        return m_list;
    }
    static constexpr double wander_distance = 1e-6;
    static constexpr int approach_periods = 8;
    /// What the observers found over the run that ended with outcome.
    SingleRun found(const RunOutcome& outcome) const {
        SingleRun r;
        r.outcome = outcome;
        r.contacts = m_forces.contacts();
        r.F_m = m_forces.max_force();
        if (m_steady) {
            r.period = m_steady->period();
            r.period_time = m_steady->time();
            r.last_far_period = m_steady->last_far_period();
            r.longer_cycle = m_steady->longer_cycle();
        }
        r.first_half_max = m_forces.first_half_max();
        r.second_half_max = m_forces.second_half_max();
        r.tail_spread = m_forces.tail_spread();
        return r;
    }

private:
    /// The steady-state detector's distance to the nearest cycle over the last
    /// approach_periods periods; asks to stop near a cycle once told to.
    class CycleDistances final : public Observer {
    public:
        explicit CycleDistances(const std::optional<SteadyStateDetector>& steady)
            : m_steady(steady) {}
        void on_step(const StepView&) override {}
        bool on_period(long n, double, const double*) override {
            if (!m_steady) return false;
            m_last[n % approach_periods] = m_steady->nearest_cycle_distance();
            m_count = std::min(m_count + 1, approach_periods);
            return m_stop && (m_steady->period() || near());
        }
        void stop_when_near() { m_stop = true; }
        [[nodiscard]] bool near() const {
            return m_steady && m_steady->nearest_cycle_distance() <= wander_distance;
        }
        [[nodiscard]] bool steady_wandering() const {
            if (m_count < approach_periods) return false;
            const auto [low, high] = std::minmax_element(std::begin(m_last), std::end(m_last));
            return std::isfinite(*high) && *low >= 1e-3 * *high;
        }

    private:
        const std::optional<SteadyStateDetector>& m_steady;
        double m_last[approach_periods] = {};
        int m_count = 0;
        bool m_stop = false;
    };

    MaxForceTracker m_forces;
    std::optional<SteadyStateDetector> m_steady;
    CycleDistances m_distances{m_steady};
    std::optional<TrajectoryRecorder> m_recorder;
    std::vector<Observer*> m_list;
};

/// Periods of the strict check of a relaxed answer (strict_check()) that relaxed at period
/// relaxed_from: a fifth of the relaxed part, and at least enough for the check's steady-state
/// watch to measure the distance to every cycle for RunWatch::approach_periods periods, plus
/// 24 (48 with the default max_steady_period 16). The check costs about that share of a strict
/// run (2-4 relaxed periods each where contacts switch often).
long strict_check_periods(const RunOptions& options, long relaxed_from) {
    const long fewest = options.max_steady_period + RunWatch::approach_periods + 24L;
    return std::max(fewest, (options.periods - relaxed_from) / 5);
}

/// The period at which a run in AccuracyMode::automatic decides whether it settles: four times
/// the contact-free row's decay time to SteadyStateDetector::far_distance (a start-up that
/// decays onto a stable orbit has come near it by then, see settled_late()), after the
/// transient, and once the distance to every cycle length has been measured for
/// RunWatch::approach_periods periods. -1
/// when the run may not relax: strict mode, a user's scheme or step, no steady-state stop, a
/// record, or too short a run (or one too short for the strict check of its relaxed answer).
long relaxation_period(const Dynamics& dyn, const RunOptions& options,
                       const SimulationHooks& hooks) {
    if (options.accuracy_mode != AccuracyMode::automatic || options.scheme != Scheme::automatic ||
        options.step || !options.stop_at_steady_state || !dyn.ground_motion().is_harmonic() ||
        hooks.trajectory || !hooks.observers.empty())
        return -1;
    RunOptions free_decay = options;
    free_decay.tolerance = SteadyStateDetector::far_distance;
    const long at =
        std::max({options.transient_periods + 1, 4 * default_transient_periods(dyn, free_decay),
                  static_cast<long>(options.max_steady_period) + RunWatch::approach_periods});
    // The relaxed part must be the larger part of the window to pay for its set-up, and leave
    // room for the check.
    const bool worth = 2 * (options.periods - at) >= options.periods - options.transient_periods &&
                       strict_check_periods(options, at) <= options.periods - at;
    return worth ? at : -1;
}

} // namespace

double window_spread(const SingleRun& r) {
    return r.outcome.status == RunStatus::completed ? std::abs(r.first_half_max - r.second_half_max)
                                                    : 0.0;
}

namespace {

/// Whether a relaxed run's answer stands on its own: it ran to its end without settling, and the
/// sampling spread of its F_m (window halves) is well above the relaxed plan's error.
bool relaxed_answer_holds(const SingleRun& r) {
    return r.outcome.status == RunStatus::completed && window_spread(r) >= relaxed_error * r.F_m;
}

/// Distance (relative to max(1, |y|_inf)) beyond which a relaxed run and its twin, started
/// 1e-8 apart, count as separated: a million times their start's distance.
constexpr double chaotic_separation = 1e-2;

/// Whether a relaxed run and its twin both ran to their common end without settling and ended
/// separated: sensitive dependence on the start, so the motion is chaotic. On an attracting
/// torus (or an orbit) a perturbation decays to a fixed phase offset of its own size and the
/// two stay about 1e-8 apart, so halves that agree there are not mistaken for chaos. A chaotic
/// run's halves can agree by chance (their maxima both approach the attractor's largest force
/// as the window grows): 1000 periods of gapchain-bench peer's row did.
bool separated(const SingleRun& main, const SingleRun& twin) {
    if (main.outcome.status != RunStatus::completed ||
        twin.outcome.status != RunStatus::completed ||
        twin.final_state.size() != main.final_state.size())
        return false;
    double scale = 1.0;
    double distance = 0.0;
    for (std::size_t i = 0; i < main.final_state.size(); ++i) {
        scale = std::max(scale, std::abs(main.final_state[i]));
        distance = std::max(distance, std::abs(main.final_state[i] - twin.final_state[i]));
    }
    return distance > chaotic_separation * scale;
}

/// Continues y on relaxed_plan() over span, feeding observers; adds the stepper's right-hand
/// sides to evaluations. The one place the relaxed part of a run (main or twin) is integrated.
RunOutcome run_relaxed(const Dynamics& dyn, std::vector<double>& y, const RunSpan& span,
                       std::span<Observer* const> observers, const ProgressCallback& progress,
                       long& evaluations) {
    const StepPlan plan = relaxed_plan(dyn);
    const std::unique_ptr<Stepper> stepper = make_stepper(plan, dyn);
    const RunOutcome outcome = run(dyn, *stepper, plan, span, y, observers, progress);
    evaluations += stepper->evaluations();
    return outcome;
}

/// Whether the relaxed plan pays for itself after a strict head of `periods` periods that took
/// `evaluations` right-hand sides: the strict plan takes at least 1.25 times the relaxed plan's
/// per period. At the default tolerance both plans step alike and differ only where the strict
/// one splits steps at contact switches: a row with few switches (measured: Nm 2, fc 200, 1.13;
/// Nm 1, fc 1000, 1.04) gains nothing a relaxed answer's checks (the strict continuation, the
/// relaxed twins) do not cost again, while its relaxed dynamics can differ from the strict ones;
/// a stiff row with many (Nm 20, fc 2000: 4.0) gains most.
bool relaxing_pays(const Dynamics& dyn, long evaluations, long periods) {
    const double relaxed = 4.0 * relaxed_plan(dyn).steps_per_period; // rk4: four per step
    return static_cast<double>(evaluations) >= 1.25 * relaxed * static_cast<double>(periods);
}

} // namespace

// The relaxation is decided here: a run still wandering at relaxation_period(), whose strict
// plan costs enough more than the relaxed one (relaxing_pays()), finishes on relaxed_plan().
SingleRun run_once(const Dynamics& dyn, const RunOptions& options, PlannedRun& planned,
                   const SimulationHooks& hooks) {
    RunWatch watch(dyn, options, hooks.trajectory, std::max(1, hooks.trajectory_every),
                   hooks.observers);
    const long relax_at = relaxation_period(dyn, options, hooks);
    if (relax_at < 0) {
        SingleRun r = watch.found(planned.run(watch.observers(), hooks.progress));
        r.evaluations = planned.evaluations();
        r.final_state = planned.state();
        return r;
    }
    const RunSpan head{relax_at, options.transient_periods, 0.0, 0};
    // The head is the first relax_at periods of the run: its fractions are of the whole run.
    ProgressCallback head_progress;
    if (hooks.progress)
        head_progress = [&](double done) {
            return hooks.progress(done * static_cast<double>(relax_at) /
                                  static_cast<double>(options.periods));
        };
    const RunOutcome first = planned.run(head, watch.observers(), head_progress);
    const RunSpan rest{options.periods, options.transient_periods, first.t_end, relax_at};
    if (first.status != RunStatus::completed || !watch.wandering() ||
        !relaxing_pays(dyn, planned.evaluations(), relax_at)) {
        RunOutcome outcome = first;
        if (first.status == RunStatus::completed) {
            outcome = planned.run(rest, watch.observers(), hooks.progress);
            outcome.steps += first.steps;
        }
        SingleRun r = watch.found(outcome);
        r.evaluations = planned.evaluations();
        r.final_state = planned.state();
        return r;
    }
    std::vector<double> y = planned.state();
    long evaluations = planned.evaluations();
    RunOutcome outcome = run_relaxed(dyn, y, rest, watch.observers_stopping_near_a_cycle(),
                                     hooks.progress, evaluations);
    outcome.steps += first.steps;
    SingleRun r = watch.found(outcome);
    r.evaluations = evaluations;
    r.final_state = std::move(y);
    r.relaxed_from = relax_at;
    r.relax_state = planned.state();
    r.relax_time = first.t_end;
    return r;
}

std::vector<double> perturbed(std::vector<double> x) {
    double scale = 1.0;
    for (double v : x)
        scale = std::max(scale, std::abs(v));
    x[0] += 1e-8 * scale;
    return x;
}

SingleRun relaxed_twin(const Dynamics& dyn, const RunOptions& options, const SingleRun& main,
                       const ProgressCallback& progress) {
    RunWatch watch(dyn, options, {}, 1, {});
    std::vector<double> y = perturbed(main.relax_state);
    const RunSpan rest{options.periods, options.transient_periods, main.relax_time,
                       main.relaxed_from};
    long evaluations = 0;
    SingleRun r = watch.found(run_relaxed(dyn, y, rest, watch.observers(), progress, evaluations));
    r.evaluations = evaluations;
    r.final_state = std::move(y);
    return r;
}

namespace {

enum class StrictCheck { wanders, settles, cancelled };

/// Whether the strict dynamics, continued from the end of a relaxed run that did not settle,
/// still wander after strict_check_periods(), or come near a cycle. The relaxed plan (switches
/// not split) can wander on where the strict dynamics settle: it keeps the row on a chaotic
/// saddle that the strict dynamics leave, a motion the twin, on the same plan, shares. Measured
/// on the paper-scale sample (seed 1, 247 relaxed answers, each continued strict for 1000
/// periods): 16 came within 1e-3 of a cycle, 13 after 17-42 periods, 2 after 109 and 153, 1
/// after 348; none of the other 231 did (a 17th answer, whose strict run from rest settles,
/// did not within 1000). Escape from a saddle is memoryless, so a check this long misses a slow
/// one (docs/performance.md).
StrictCheck strict_check(const Dynamics& dyn, RunOptions options, const SingleRun& relaxed,
                         const ProgressCallback& progress, long& evaluations) {
    options.periods = strict_check_periods(options, relaxed.relaxed_from);
    options.transient_periods = 0;
    options.accuracy_mode = AccuracyMode::strict;
    // A relaxed answer ran all its periods: its end state is at forcing phase 0, the start's.
    PlannedRun planned(dyn, options, relaxed.final_state);
    RunWatch watch(dyn, options, {}, 1, {});
    const RunOutcome outcome = planned.run(watch.observers_stopping_near_a_cycle(), progress);
    evaluations += planned.evaluations();
    if (outcome.status == RunStatus::cancelled) return StrictCheck::cancelled;
    return outcome.status == RunStatus::completed && watch.wandering() ? StrictCheck::wanders
                                                                       : StrictCheck::settles;
}

/// Whether a relaxed run's answer stands: the strict dynamics from its end do not settle
/// (strict_check()), and its halves spread at least the relaxed plan's error, or its twin (run
/// here; kept in r when it lets the answer stand) shows it chaotic and agrees with it.
/// Sets r's status to cancelled if a cancel came.
bool relaxed_answer_stands(const Dynamics& dyn, const RunOptions& options, SingleRun& r,
                           const ProgressCallback& progress) {
    if (r.outcome.status != RunStatus::completed) return false;
    // The check first: it costs less than the twin, which is wasted where the check fails.
    const StrictCheck check = strict_check(dyn, options, r, progress, r.evaluations);
    if (check == StrictCheck::cancelled) r.outcome.status = RunStatus::cancelled;
    if (check != StrictCheck::wanders) return false;
    std::shared_ptr<const SingleRun> twin;
    if (!relaxed_answer_holds(r)) {
        twin = std::make_shared<const SingleRun>(relaxed_twin(dyn, options, r, progress));
        r.evaluations += twin->evaluations;
        if (twin->outcome.status == RunStatus::cancelled) {
            r.outcome.status = RunStatus::cancelled;
            return false;
        }
        // Separated, and the two answers agree as two samples of one chaos (the multistability
        // check's allowance, with the relaxed plan's error as the least spread). A twin that
        // disagrees (another attractor, or a main F_m taken before the relaxed part, which the
        // twin does not run) sends the run to the strict plan and its full-length twin.
        const double allowance =
            3.0 * std::max({window_spread(r), window_spread(*twin), relaxed_error * r.F_m});
        if (!separated(r, *twin) || std::abs(twin->F_m - r.F_m) > allowance) return false;
    }
    r.twin = std::move(twin);
    return true;
}

} // namespace

SingleRun run_settled(const Dynamics& dyn, RunOptions options, const std::vector<double>& initial,
                      const SimulationHooks& hooks, std::optional<PlannedRun>& planned) {
    planned.emplace(dyn, options, initial);
    SingleRun r = run_once(dyn, options, *planned, hooks);
    // A cancel ends the call: a strict rerun would swallow a callback that answers false once.
    if (r.relaxed_from < 0 || r.outcome.status == RunStatus::cancelled) return r;
    // The runs after the first report its end, as simulate()'s later runs do: a progress
    // display never goes back (they may be cancelled all the same).
    SimulationHooks finishing = hooks;
    if (hooks.progress) finishing.progress = [&](double) { return hooks.progress(1.0); };
    if (relaxed_answer_stands(dyn, options, r, finishing.progress) ||
        r.outcome.status == RunStatus::cancelled)
        return r;
    const long spent = r.evaluations;
    options.accuracy_mode = AccuracyMode::strict;
    planned.emplace(dyn, options, initial);
    r = run_once(dyn, options, *planned, finishing);
    r.evaluations += spent;
    return r;
}

} // namespace gapchain::detail
