#include "gapchain/poincare.hpp"

#include "detail/check.hpp"
#include "detail/dense_output.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace gapchain {

SectionVariable SectionVariable::parse(std::string_view name, int bodies, const std::string& key) {
    auto fail = [&]() -> SectionVariable {
        throw std::invalid_argument(key + ": must be t, u1..u" + std::to_string(bodies) +
                                    ", v1..v" + std::to_string(bodies) + ", g0..g" +
                                    std::to_string(bodies) + " or F0..F" + std::to_string(bodies) +
                                    ", got \"" + std::string(name) + "\"");
    };
    if (name == "t") return {Kind::time, 0};
    // One spelling per variable: "u01" is not "u1" (a leading zero, except g0 and F0 themselves).
    if (name.size() < 2 || (name[1] == '0' && name.size() > 2)) return fail();
    int index = 0;
    for (char c : name.substr(1)) {
        if (c < '0' || c > '9' || index > 10'000'000) return fail();
        index = index * 10 + (c - '0');
    }
    switch (name[0]) {
    case 'u':
        if (index < 1 || index > bodies) return fail();
        return {Kind::displacement, index - 1};
    case 'v':
        if (index < 1 || index > bodies) return fail();
        return {Kind::velocity, index - 1};
    case 'g':
        if (index > bodies) return fail();
        return {Kind::gap, index};
    case 'F':
        if (index > bodies) return fail();
        return {Kind::force, index};
    default: return fail();
    }
}

SectionVariable SectionVariable::parse_state(std::string_view name, int bodies,
                                             const std::string& key) {
    const std::string n = std::to_string(bodies);
    const std::string refusal = key + ": must be a state variable, u1..u" + n + ", v1..v" + n +
                                ", g0..g" + n + " or F0..F" + n + ", got \"" + std::string(name) +
                                "\"";
    try {
        const SectionVariable v = parse(name, bodies, key);
        if (v.kind != Kind::time) return v;
    } catch (const std::invalid_argument&) {
    }
    throw std::invalid_argument(refusal);
}

std::vector<SectionVariable> SectionVariable::whole_state(int bodies) {
    std::vector<SectionVariable> state;
    for (const auto kind : {Kind::displacement, Kind::velocity})
        for (int i = 0; i < bodies; ++i)
            state.push_back({kind, i});
    return state;
}

SectionVariable SectionVariable::parse_trigger(std::string_view name, int bodies,
                                               const std::string& key) {
    const std::string n = std::to_string(bodies);
    const std::string refusal = key + ": must be a linear signal of the state, u1..u" + n +
                                ", v1..v" + n + " or g0..g" + n + ", got \"" + std::string(name) +
                                "\"";
    try {
        const SectionVariable v = parse(name, bodies, key);
        if (v.kind != Kind::time && v.kind != Kind::force) return v;
    } catch (const std::invalid_argument&) {
    }
    throw std::invalid_argument(refusal);
}

std::string SectionVariable::name() const {
    // Built with append rather than "u" + std::string: GCC 12 warns falsely (-Wrestrict) on
    // the latter.
    std::string s;
    switch (kind) {
    case Kind::displacement: s = "u"; break;
    case Kind::velocity: s = "v"; break;
    case Kind::gap: s = "g"; break;
    case Kind::force: s = "F"; break;
    case Kind::time: return "t";
    }
    const bool body = kind == Kind::displacement || kind == Kind::velocity;
    s.append(std::to_string(body ? index + 1 : index));
    return s;
}

double SectionVariable::value(const Dynamics& dyn, double t, const double* y) const {
    switch (kind) {
    case Kind::displacement: return y[index];
    case Kind::velocity: return y[dyn.bodies() + index];
    case Kind::gap: return dyn.gap(index, y);
    case Kind::force: return dyn.force(index, y);
    case Kind::time: return t;
    }
    return 0.0;
}

void validate(const SectionSpec& spec, int bodies) {
    if (spec.kind == SectionSpec::Kind::stroboscopic) {
        if (!(spec.phase >= 0.0 && spec.phase < 1.0))
            throw std::invalid_argument("section.phase: must be in [0, 1), got " +
                                        detail::format_number(spec.phase));
    } else {
        using K = SectionVariable::Kind;
        const auto k = spec.trigger.kind;
        if (k != K::displacement && k != K::velocity && k != K::gap)
            throw std::invalid_argument("section.trigger: must be a displacement, velocity or "
                                        "gap (a linear signal of the state), got " +
                                        spec.trigger.name());
        detail::require_range("section.level", spec.level, -1e12, 1e12);
    }
    if (spec.record.empty())
        throw std::invalid_argument("section.record: needs at least one variable");
    for (const auto& v : spec.record) {
        const int limit = (v.kind == SectionVariable::Kind::displacement ||
                           v.kind == SectionVariable::Kind::velocity)
                              ? bodies - 1
                              : bodies;
        if (v.index < 0 || v.index > limit)
            throw std::invalid_argument("section.record: " + v.name() + " is outside a row of " +
                                        std::to_string(bodies) + " bodies");
        if (std::count_if(spec.record.begin(), spec.record.end(),
                          [&](const SectionVariable& w) { return w.name() == v.name(); }) > 1)
            throw std::invalid_argument("section.record: " + v.name() + " given twice");
    }
}

PoincareSampler::PoincareSampler(const Dynamics& dyn, SectionSpec spec, SectionSink sink)
    : m_dyn(dyn), m_spec(std::move(spec)), m_sink(std::move(sink)), m_state(dyn.dimension()) {
    validate(m_spec, dyn.bodies());
    require_harmonic(dyn, "poincare");
    m_point.values.resize(m_spec.record.size());
}

PoincareSampler::~PoincareSampler() = default;

void PoincareSampler::emit(double t, const double* y) {
    m_point.t = t;
    for (std::size_t k = 0; k < m_spec.record.size(); ++k)
        m_point.values[k] = m_spec.record[k].value(m_dyn, t, y);
    ++m_count;
    m_sink(m_point);
}

void PoincareSampler::state_at(const StepView& step, double t) {
    // The stepper's own dense output where it has one (exact), else the quintic interpolant,
    // built once per step.
    if (step.stepper != nullptr && step.stepper->dense_state(t, m_state.data())) return;
    if (!m_interpolant || m_interpolant->start() != step.t0)
        m_interpolant = std::make_unique<detail::StepInterpolant>(m_dyn, step);
    m_interpolant->state(t, m_state.data());
}

double PoincareSampler::trigger_value(const double* y) const {
    return m_spec.trigger.value(m_dyn, 0.0, y) - m_spec.level;
}

void PoincareSampler::on_step(const StepView& step) {
    if (!step.recording) return;
    if (m_spec.kind == SectionSpec::Kind::stroboscopic) {
        const double period = m_dyn.period();
        // Section times from absolute time (a run may start at any t): the one in the period
        // holding t0 and the next, which a step ending on a boundary may reach.
        const double first = std::floor(step.t0 / period);
        for (double n = first; n <= first + 1.0; n += 1.0) {
            const double ts = (n + m_spec.phase) * period;
            const double tol = 1e-12 * period * (1.0 + std::abs(n));
            if (ts <= step.t0 + tol || ts > step.t1 + tol) continue;
            if (std::abs(ts - step.t1) <= tol) {
                emit(ts, step.y1);
            } else {
                state_at(step, ts);
                emit(ts, m_state.data());
            }
        }
        return;
    }
    const double s0 = trigger_value(step.y0);
    const double s1 = trigger_value(step.y1);
    const bool up = s0 < 0.0 && s1 >= 0.0;
    const bool down = s0 > 0.0 && s1 <= 0.0;
    if (up || down) {
        if (wanted(up)) emit_crossing(step, step.t0, step.t1, s0);
        return;
    }
    emit_dip(step, s0, s1);
}

void PoincareSampler::emit_dip(const StepView& step, double s0, double s1) {
    // No sign change between the ends, yet the trigger may cross the level and come back
    // inside the step: a shallow dip (Fig 13's row at f_r = 3.0 dips u1 below 0 to v1 = -0.0108
    // once a period; the exact scheme at 1e-8 and rkf45 at 1e-3 stepped over it and found 60
    // of rk8pd's 120 crossings). The trigger then turns inside the step, its rate changing sign
    // between the ends; its reach is bounded as the force tracker bounds a peak's. A step that
    // starts exactly on the level (the step before ended on a crossing) is left alone: its
    // side is unknown, and a return within one step after a crossing is rare.
    if (s0 == 0.0) return;
    const double r0 = trigger_rate(step.t0, step.y0);
    if ((s0 > 0.0) == (r0 > 0.0)) return; // moving away from the level: the turn is on its side
    const double r1 = trigger_rate(step.t1, step.y1);
    if (!(r0 * r1 < 0.0)) return;
    const double h = step.t1 - step.t0;
    const double reach =
        s0 > 0.0 ? std::min(s0, s1) - 0.5 * h * (r1 - r0) : std::max(s0, s1) + 0.5 * h * (r0 - r1);
    if ((reach > 0.0) == (s0 > 0.0)) return;
    const double turn = bisect(step, step.t0, step.t1, [&](double t, const double* y) {
        return (trigger_rate(t, y) > 0.0) == (r0 > 0.0);
    });
    const double at_turn = trigger_value(m_state.data());
    // A touch within round-off of the level is no crossing: two runs would disagree on it.
    const double floor = 1e-12 * std::max({std::abs(s0 + m_spec.level), std::abs(s1 + m_spec.level),
                                           std::abs(m_spec.level)});
    if ((at_turn > 0.0) == (s0 > 0.0) || std::abs(at_turn) <= floor) return;
    const bool first_up = s0 < 0.0;
    if (wanted(first_up)) emit_crossing(step, step.t0, turn, s0);
    if (wanted(!first_up)) emit_crossing(step, turn, step.t1, at_turn);
}

bool PoincareSampler::wanted(bool up) const {
    return m_spec.direction == CrossingDirection::both ||
           (m_spec.direction == CrossingDirection::up) == up;
}

double PoincareSampler::trigger_rate(double t, const double* y) const {
    // Read at the step's ends as they are, with no inside offset (dense_output.hpp): a rate of
    // u, v or g is continuous across a contact switch under every law (a contact's force
    // vanishes with its penetration): unlike the jerk, it does not jump where an end lies a
    // little past a switch.
    const int n = m_dyn.bodies();
    const int i = m_spec.trigger.index;
    switch (m_spec.trigger.kind) {
    case SectionVariable::Kind::displacement: return y[n + i];
    case SectionVariable::Kind::velocity: return m_dyn.body_acceleration(i, m_dyn.ground(t), y);
    case SectionVariable::Kind::gap: return m_dyn.gap_rate(i, y + n);
    default: return 0.0; // validate() admits u, v and g only
    }
}

double PoincareSampler::bisect(const StepView& step, double lo, double hi,
                               const std::function<bool(double, const double*)>& on_lo_side) {
    for (int it = 0; it < 80 && hi - lo > 1e-15 * (1.0 + std::abs(hi)); ++it) {
        const double mid = 0.5 * (lo + hi);
        state_at(step, mid);
        if (on_lo_side(mid, m_state.data()))
            lo = mid;
        else
            hi = mid;
    }
    const double t = 0.5 * (lo + hi);
    state_at(step, t);
    return t;
}

void PoincareSampler::emit_crossing(const StepView& step, double lo, double hi, double s_lo) {
    // The trigger is a linear combination of state components, so its interpolant is the
    // same combination of theirs; root-find on it by bisection to full precision.
    const double tc = bisect(step, lo, hi, [&](double, const double* y) {
        return (trigger_value(y) < 0.0) == (s_lo < 0.0);
    });
    emit(tc, m_state.data());
}

int detect_period(const std::vector<SectionPoint>& points, int max_period, double tolerance) {
    SectionRepeats repeats(max_period);
    for (const auto& p : points)
        repeats.add(p.values);
    return repeats.period(tolerance);
}

SectionRepeats::SectionRepeats(int max_period)
    : m_max_period(max_period), m_largest_difference(static_cast<std::size_t>(max_period) + 1) {
    detail::require_range("max_period", max_period, 1, 1000);
}

void SectionRepeats::add(const std::vector<double>& values) {
    if (!m_recent.empty() && values.size() != m_recent.back().size())
        throw std::invalid_argument("section point: " + std::to_string(values.size()) +
                                    " values after points of " +
                                    std::to_string(m_recent.back().size()));
    for (double v : values)
        m_scale = std::max(m_scale, std::abs(v));
    for (std::size_t k = 1; k <= m_recent.size(); ++k) {
        const std::vector<double>& earlier = m_recent[m_recent.size() - k];
        double& largest = m_largest_difference[k];
        for (std::size_t c = 0; c < values.size(); ++c)
            largest = std::max(largest, std::abs(values[c] - earlier[c]));
    }
    m_recent.push_back(values);
    if (static_cast<int>(m_recent.size()) > m_max_period) m_recent.pop_front();
    ++m_count;
}

int SectionRepeats::period(double tolerance, bool distinct_cycle) const {
    detail::require_range("period_tolerance", tolerance, 0.0, 1.0, detail::Bound::open_low);
    const double tol = tolerance * (1.0 + m_scale);
    for (int k = 1; k <= m_max_period && 2L * k <= m_count; ++k) {
        if (m_largest_difference[static_cast<std::size_t>(k)] > tol) continue;
        if (!distinct_cycle) return k;
        const std::vector<double>& last = m_recent.back();
        for (int j = 1; j < k; ++j) {
            const std::vector<double>& earlier = m_recent[m_recent.size() - 1 - j];
            double difference = 0.0;
            for (std::size_t c = 0; c < last.size(); ++c)
                difference = std::max(difference, std::abs(last[c] - earlier[c]));
            if (difference <= tol) return j;
        }
        return k;
    }
    return 0;
}

namespace {

/// A stroboscopic section's time (a multiple of the period), and an event section's trigger,
/// which equals the level at every point, carry no error of the trajectory; an event section's
/// crossing times do (rkf45 at its default tolerance on Fig 13's row at f_r = 2.2 is 3.7e-6
/// off rk8pd at 1e-10, a reviewer's probe, helper-75).
bool estimated(const SectionSpec& spec, const SectionVariable& v) {
    const bool event = spec.kind == SectionSpec::Kind::event;
    if (v.kind == SectionVariable::Kind::time) return event;
    return !(event && v.kind == spec.trigger.kind && v.index == spec.trigger.index);
}

} // namespace

void RecordTailRepeats::add(const SectionPoint& point) {
    // Neither t nor an event's trigger (at the level on every point) tells a repeat: recorded
    // alone, they read "periodic" on Fig 13's chaotic row at f_r = 3.3 (a reread, helper-89).
    std::vector<double> values;
    values.reserve(point.values.size());
    for (std::size_t i = 0; i < point.values.size(); ++i) {
        const SectionVariable& v = m_spec.record[i];
        if (v.kind != SectionVariable::Kind::time && estimated(m_spec, v))
            values.push_back(point.values[i]);
    }
    m_last.push_back(std::move(values));
    if (m_last.size() > 3 * static_cast<std::size_t>(max_repeat)) m_last.pop_front();
    ++m_count;
}

int RecordTailRepeats::period() const {
    if (m_last.empty() || m_last.front().empty()) return 0;
    const auto held = static_cast<long>(m_last.size());
    double scale = 0.0;
    for (const auto& values : m_last)
        for (double v : values)
            scale = std::max(scale, std::abs(v));
    const double tol = repeat_tolerance * (1.0 + scale);
    for (long k = 1; k <= max_repeat; ++k) {
        const long window = std::max(2 * k, std::min(m_count / 2, 2L * max_repeat));
        if (window + k > held) break;
        bool repeats = true;
        for (long i = held - window; i < held && repeats; ++i) {
            const auto& now = m_last[static_cast<std::size_t>(i)];
            const auto& before = m_last[static_cast<std::size_t>(i - k)];
            for (std::size_t c = 0; c < now.size() && repeats; ++c)
                repeats = std::abs(now[c] - before[c]) <= tol;
        }
        if (repeats) return static_cast<int>(k);
    }
    return 0;
}

RunOutcome take_section(const Dynamics& dyn, const RunOptions& options, const SectionSpec& spec,
                        const SectionSink& sink, const std::vector<double>& initial,
                        const ProgressCallback& progress) {
    PlannedRun planned(dyn, options, initial);
    PoincareSampler sampler(dyn, spec, sink);
    Observer* observers[] = {&sampler};
    return planned.run(observers, progress);
}

namespace {

/// Asks the run to stop once the sampler it watches has emitted `wanted` points: the finer run
/// needs no more than the main points it is set against.
class EnoughPoints final : public Observer {
public:
    EnoughPoints(const PoincareSampler& sampler, long wanted)
        : m_sampler(sampler), m_wanted(wanted) {}
    void on_step(const StepView&) override {}
    bool on_period(long, double, const double*) override { return m_sampler.count() >= m_wanted; }

private:
    const PoincareSampler& m_sampler;
    long m_wanted;
};

} // namespace

namespace {

/// The finer run's plan and length, or why there is none: its tolerance cannot go a tenth
/// lower (rkf45 and rk8pd stop at 1e-12), or it would exceed run.max_work (it runs only as far
/// as the points need: a stroboscopic section the transient and one period a point).
struct FinerRun {
    StepPlan plan;
    RunOptions options;
    std::string not_run;
    bool main_exact = false; ///< the main run is on the exact scheme (compared with rk8pd)
};

FinerRun finer_run(const Dynamics& dyn, const RunOptions& options, const SectionSpec& spec,
                   std::size_t points) {
    const StepPlan plan = plan_run(dyn, options);
    FinerRun f{finer_plan(dyn, plan, 10.0), options, {}, plan.scheme == Scheme::exact};
    if (f.main_exact) {
        // The exact scheme on a finer interval shares its eigendecompositions, and so its
        // round-off: on Fig 13's chaotic row at f_r = 3.35 the two agreed to 3e-11 where rk8pd
        // at 1e-12 lay 1.7e-9 away, amplified over the record (a reviewer's probe, helper-77).
        // It is set against rk8pd at the tightest tolerance instead.
        f.options.scheme = Scheme::rk8pd;
        f.options.tolerance = 1e-12;
        // Not the exact run's step: rk8pd's output interval bounds the steps its crossings are
        // interpolated over, and at step 0.05 it missed a dip the exact run found, which then
        // read as the exact run's fault (helper-78).
        f.options.step.reset();
        f.plan = plan_run(dyn, f.options);
    } else if (traits(plan.scheme).adaptive &&
               f.plan.tolerance > plan.tolerance / 10.0 * (1 + 1e-9))
        f.not_run = "the run's tolerance is within 10 times the smallest (1e-12): no finer run";
    const long transient = with_transient_resolved(dyn, options).transient_periods;
    if (spec.kind == SectionSpec::Kind::stroboscopic)
        f.options.periods = std::min(options.periods, transient + static_cast<long>(points) + 1);
    const double work = run_work(dyn, f.plan, static_cast<double>(f.options.periods));
    if (f.not_run.empty() && work > options.max_work)
        f.not_run = "the finer run would take " + detail::format_number(work) +
                    " body-steps, above run.max_work = " + detail::format_number(options.max_work);
    return f;
}

/// The main run's points set against the finer run's, point k of one against point m of the
/// other. A variable differs at a point when it differs by more than 1e-3 of its own largest
/// |value| (`largest`): units differ between variables (u, v, gaps, forces). Not the time,
/// whose largest value is the record's length.
struct SectionPairing {
    const SectionSpec& spec;
    const std::vector<SectionPoint>& main_points;
    const std::vector<SectionPoint>& points;
    const std::vector<double>& largest;
    double period;
    long compared;

    /// The largest difference of a variable between two points, in units of its largest |value|.
    [[nodiscard]] double distance(const SectionPoint& x, const SectionPoint& y) const {
        double d = 0.0;
        for (std::size_t i = 0; i < spec.record.size(); ++i)
            if (estimated(spec, spec.record[i]) &&
                spec.record[i].kind != SectionVariable::Kind::time && largest[i] > 0.0)
                d = std::max(d, std::abs(x.values[i] - y.values[i]) / largest[i]);
        return d;
    }
    /// distance() between the main run's point k and the finer run's point m.
    [[nodiscard]] double difference(long k, long m) const {
        return distance(main_points[k], points[m]);
    }
    /// Whether a run's points from k on repeat: some P <= 128 brings each of twenty points back
    /// within 1e-3 (of each variable's largest value) of itself P points later; the twenty from
    /// k, or the last twenty that have a point P later. A chaotic record never does; a periodic
    /// one does to round-off, however far it lies from the other run's.
    [[nodiscard]] bool recurrent(const std::vector<SectionPoint>& run, long k) const {
        const auto n = static_cast<long>(run.size());
        for (long P = 1; P <= 128 && 20 + P <= n; ++P) {
            const long first = std::min(k, n - 20 - P);
            bool repeats = true;
            for (long j = first; j < first + 20 && repeats; ++j)
                repeats = distance(run[j], run[j + P]) <= 1e-3;
            if (repeats) return true;
        }
        return false;
    }
    [[nodiscard]] double apart(long k, long m) const {
        return std::abs(main_points[k].t - points[m].t);
    }
    /// Whether the points agree once one run's are shifted by the one or two crossings it found
    /// more: a graze found by one run only, both directions (times 0.067 apart at the first
    /// wrong pair, a reviewer's probe, helper-78).
    [[nodiscard]] bool shifted_match(long k) const {
        // Each run may hold points beyond the compared ones: the shifted partner is looked for
        // among all of them (helper-80: an extra crossing at the last compared point read as
        // chaos).
        const double unshifted = apart(k, k);
        const auto finer_count = static_cast<long>(points.size());
        const auto main_count = static_cast<long>(main_points.size());
        for (long s = 1; s <= 2; ++s)
            if ((k + s < finer_count && apart(k, k + s) < 0.1 * unshifted &&
                 difference(k, k + s) <= 1e-3) ||
                (k + s < main_count &&
                 std::abs(main_points[k + s].t - points[k].t) < 0.1 * unshifted &&
                 difference(k + s, k) <= 1e-3))
                return true;
        return false;
    }
    /// Whether the runs find crossings at rates more than `by` (relative) apart: as many points
    /// span another time.
    /// rk4 at step 0.02 steps over a dip pair of v2 = 2.12 each period that its finer run finds
    /// (Fig 13's row at f_r = 3.0, 120 crossings against 240), and no point of it agrees with
    /// any of the finer run's (helper-78).
    [[nodiscard]] bool rates_differ(double by) const {
        // The finer run stops once it has as many points as the main run: fewer means it found
        // fewer over the whole record. Beyond the sampling spread of a count only: two chaotic
        // records of a rare crossing differ by about its square root (Fig 13 at f_r 3.3, g2 =
        // 0.0105: 40 crossings against 24, a reviewer's reread, helper-83).
        const auto main_count = static_cast<double>(main_points.size());
        if (main_count - static_cast<double>(points.size()) >
            std::max(by * main_count, 3.0 * std::sqrt(main_count)))
            return true;
        if (compared < 50) return false;
        // Both spans from the main run's first point: the runs start recording together.
        const auto last = static_cast<std::size_t>(compared - 1);
        const double span = main_points[last].t - main_points[0].t;
        const double finer_span = points[last].t - main_points[0].t;
        return std::abs(span - finer_span) > by * std::max(span, finer_span);
    }
};

/// a.parted_at and a.crossings_differ: where the main run's points and the finer run's part.
void set_parting(const SectionPairing& p, SectionAccuracy& a) {
    const bool event = p.spec.kind == SectionSpec::Kind::event;
    const auto mispaired = [&](long k) { return event && p.apart(k, k) > 0.25 * p.period; };
    // An event section's runs that found different crossings pair every point beyond wrongly:
    // their rates differ by a quarter (rk4 at step 0.02), the points agree once shifted, or
    // their crossing times are more than a quarter period apart (rk4 at 1e-4 steps over a dip
    // its finer run finds).
    if (event && p.rates_differ(0.25)) {
        long k = 0;
        while (k < a.compared && !mispaired(k) && p.difference(k, k) <= 1e-3)
            ++k;
        // Every compared point agreeing (the finer run's fewer crossings lie beyond them) parts
        // them after the last, and the error covers them all (helper-83).
        a.parted_at = k;
        a.crossings_differ = true;
        return;
    }
    // The runs part (a chaotic record) where they differ, more than half of that point and the
    // nine after it differ, and more than half of the twenty from it lie more than 1e-2 of the
    // variable's largest value apart: a chaotic record stays apart once it has parted, and its
    // points spread over the attractor (a chaotic transient may later settle both runs on one
    // orbit again: parting at f_r = 3.25 from rest, g2 = 0 both ways, read as crossings found by
    // one run only, helper-79). Fewer than twenty points left: no parting. Points that differ by
    // a bounded amount, or at half the points at most (a periodic row's dips), are this start's
    // all the same, and widen the error instead (helper-80 built both from one point differing
    // by more than 1e-2: last, or among a coarse run's differences): a run too coarse to follow
    // its points (rk4 at step 0.01 on Fig 13's row at f_r = 2.5 is 1.6e-3 to 3.4e-3 off at 2
    // points in 3), or ill-conditioned ones, the velocity at a shallow crossing moving by a/v
    // times the depth's error (Fig 13's row at f_r = 3.0 dips 1.7e-6 below u1 = 0 at v1 =
    // -0.0108; rkf45 at 1e-3 and its finer run differ there by 3e-3 and agree again at the
    // next, deep crossing, which read "parted at 1, a chaotic record").
    std::vector<double> d(static_cast<std::size_t>(a.compared));
    for (long k = 0; k < a.compared; ++k)
        d[static_cast<std::size_t>(k)] = p.difference(k, k);
    // Both runs repeating is no chaos, however far apart they lie: rk4 at step 0.02 on Fig 13's
    // periodic row at f_r = 3.0 settles 4.7e-3 (in u1) from its finer run, and read "a chaotic
    // record that parted before it began" (helper-82).
    const auto chaotic = [&](long k) {
        if (k + 20 > a.compared) return false;
        const auto from = d.begin() + k;
        const auto differing = std::count_if(from, from + 10, [](double x) { return x > 1e-3; });
        const auto apart = std::count_if(from, from + 20, [](double x) { return x > 1e-2; });
        return differing > 5 && apart > 10 &&
               !(p.recurrent(p.main_points, k) && p.recurrent(p.points, k));
    };
    for (long k = 0; k < a.compared; ++k) {
        const bool off_time = mispaired(k);
        if (!off_time && d[static_cast<std::size_t>(k)] <= 1e-3) continue;
        const bool shifted = event && p.shifted_match(k);
        const bool chaos = chaotic(k);
        if (!shifted && !chaos && !off_time) continue;
        a.parted_at = k;
        a.crossings_differ = shifted || (off_time && !chaos);
        // Only the finer run repeating is no proof of chaos: the run may be too coarse to
        // follow the finer run's orbit (helper-82's case, rk4 at step 0.03), so the result
        // says both readings.
        a.finer_repeats = !a.crossings_differ && p.recurrent(p.points, k);
        return;
    }
}

/// a.parted_at, a.crossings_differ and a.error from the compared points of the main and the
/// finer run.
void set_point_errors(const SectionSpec& spec, const std::vector<SectionPoint>& main_points,
                      const std::vector<SectionPoint>& points, bool exact, double period,
                      SectionAccuracy& a) {
    const std::size_t variables = spec.record.size();
    std::vector<double> largest(variables, 0.0), difference(variables, 0.0);
    for (long k = 0; k < a.compared; ++k)
        for (std::size_t i = 0; i < variables; ++i)
            largest[i] = std::max(largest[i], std::abs(main_points[k].values[i]));
    set_parting({spec, main_points, points, largest, period, a.compared}, a);
    if (a.crossings_differ && a.parted_at == 0) {
        a.not_estimated = "the finer run found other crossings from the first point on";
        return;
    }
    // Runs that part from the first point on are a chaotic record that parted before it began:
    // its points are bounded by their largest difference over every point compared, twice, the
    // attractor's extent (a run too coarse to follow its points, which read so until
    // 2026-11-29, now never parts and gets the same bound).
    const long agreed = a.parted_at < 0 || a.parted_at == 0 ? a.compared : a.parted_at;
    for (long k = 0; k < agreed; ++k)
        for (std::size_t i = 0; i < variables; ++i)
            difference[i] =
                std::max(difference[i], std::abs(main_points[k].values[i] - points[k].values[i]));
    // The exact scheme's finer run shares its eigendecompositions and so its round-off: the two
    // agreed to 0 where rk8pd at 1e-11 was 1.5e-12 away in u1 (6.8e-12 of its largest value) and
    // 6e-12 in v3 (helper-75). Its floor is 3e-11 of the variable's largest value.
    const double floor = exact ? 3e-11 : 0.0;
    for (std::size_t i = 0; i < variables; ++i)
        if (estimated(spec, spec.record[i]))
            a.error[i] = std::max(2.0 * difference[i], floor * largest[i]);
}

} // namespace

SectionAccuracy section_accuracy(const Dynamics& dyn, const RunOptions& options,
                                 const SectionSpec& spec, const std::vector<double>& initial,
                                 const std::vector<SectionPoint>& main_points,
                                 const ProgressCallback& progress) {
    SectionAccuracy a;
    const std::size_t variables = spec.record.size();
    a.error.assign(variables, std::numeric_limits<double>::quiet_NaN());
    const FinerRun finer = finer_run(dyn, options, spec, main_points.size());
    const bool exact = finer.main_exact;
    char tolerance[64];
    std::snprintf(tolerance, sizeof tolerance, "tolerance %.3g, half the output interval",
                  finer.plan.tolerance);
    a.comparison = exact                                ? "rk8pd at tolerance 1e-12"
                   : traits(finer.plan.scheme).adaptive ? tolerance
                                                        : "half the step";
    if (!finer.not_run.empty()) {
        a.not_estimated = finer.not_run;
        return a;
    }
    std::vector<SectionPoint> points;
    PoincareSampler sampler(dyn, spec, [&points](const SectionPoint& p) { points.push_back(p); });
    // At least one: a run with no point is checked too (a level just inside an extremum that
    // it missed and its finer run crosses), not stopped at the first period end.
    EnoughPoints enough(sampler, std::max<long>(1, static_cast<long>(main_points.size())));
    Observer* observers[] = {&sampler, &enough};
    PlannedRun planned(dyn, finer.options, finer.plan, initial);
    const RunOutcome outcome = planned.run(observers, progress);
    a.status = outcome.status == RunStatus::steady_state ? RunStatus::completed : outcome.status;
    if (a.status != RunStatus::completed) {
        a.not_estimated = "the finer run ended " + std::string(to_string(a.status));
        return a;
    }
    a.compared = static_cast<long>(std::min(points.size(), main_points.size()));
    if (a.compared == 0) {
        // One run found crossings and the other none over the whole record: a level within the
        // run's error of an extremum (helper-82: u1 = 0.05939, 1.7e-6 above its largest value,
        // 100 points against none). A finer run for a run without points stops at its first.
        a.crossings_differ =
            spec.kind == SectionSpec::Kind::event && (!main_points.empty() || !points.empty());
        a.parted_at = a.crossings_differ ? 0 : -1;
        a.not_estimated = !a.crossings_differ ? "no point to compare"
                          : points.empty()
                              ? "the finer run found no crossing where the run found " +
                                    std::to_string(main_points.size())
                              : "the run found no crossing where the finer run found some";
        return a;
    }
    set_point_errors(spec, main_points, points, exact, dyn.period(), a);
    return a;
}

} // namespace gapchain
