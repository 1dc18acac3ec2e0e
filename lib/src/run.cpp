#include "gapchain/run.hpp"

#include "detail/check.hpp"
#include "detail/hermite.hpp"
#include "detail/steppers.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

namespace gapchain {

std::string_view to_string(RunStatus status) {
    switch (status) {
    case RunStatus::completed: return "completed";
    case RunStatus::steady_state: return "steady_state";
    case RunStatus::non_finite: return "non_finite";
    case RunStatus::cancelled: return "cancelled";
    }
    return "?";
}

AccuracyMode parse_accuracy_mode(std::string_view name) {
    if (name == "auto") return AccuracyMode::automatic;
    if (name == "strict") return AccuracyMode::strict;
    throw std::invalid_argument("run.accuracy_mode: must be one of auto, strict, got \"" +
                                std::string(name) + "\"");
}

std::string_view to_string(AccuracyMode mode) {
    return mode == AccuracyMode::strict ? "strict" : "auto";
}

namespace {

/// Index of the first body whose displacement or velocity is not finite, or -1.
int first_non_finite_body(const std::vector<double>& y, int n) {
    for (int i = 0; i < 2 * n; ++i)
        if (!std::isfinite(y[i])) return i % n;
    return -1;
}

/// A contact switch inside a step: when, and which contact.
struct Switch {
    double t;
    int gap;
};

/// Gaps and gap rates of every contact at one state (Nm + 1 entries each), carried from step
/// to step so that each is computed once.
struct GapState {
    std::vector<double> value, rate;
    std::vector<double> candidate; // first_switch()'s scratch: may_cross() of the step ending here
    explicit GapState(const Dynamics& dyn)
        : value(dyn.gaps()), rate(dyn.gaps()), candidate(dyn.gaps()) {}
    void of(const Dynamics& dyn, const double* y) {
        dyn.gaps(y, value.data());
        dyn.gap_rates(y + dyn.bodies(), rate.data());
    }
};

/// The ends of one step as crossing_in_step() reads them; the ground terms and the noise floor
/// are computed on first use (most steps need neither).
class StepEnds {
public:
    StepEnds(const Dynamics& dyn, double t0, double t1, const double* y0, const double* y1)
        : y0(y0), y1(y1), m_dyn(dyn), m_t0(t0), m_t1(t1) {}
    double ground0() {
        if (std::isnan(m_ground0)) m_ground0 = m_dyn.ground(m_t0);
        return m_ground0;
    }
    double ground1() {
        if (std::isnan(m_ground1)) m_ground1 = m_dyn.ground(m_t1);
        return m_ground1;
    }
    /// A turn within this of the surface is round-off: bodies that move in lockstep at e_r = 0
    /// keep gaps of round-off size that turn at random. 1e-12 of the largest of the
    /// displacements and the ground term (a reduced acceleration, up to 4 pi^2 times the
    /// ground amplitude): a floor near 4e-11 in gap units over most of a harmonic period (0
    /// only where the ground term and every displacement vanish together); grazes shallower
    /// than that are left alone (clearances are 1e-2 and more, and a graze of 4e-11 moves
    /// nothing measurable).
    double floor() {
        if (std::isnan(m_floor)) {
            double scale = std::abs(ground0());
            for (int i = 0; i < m_dyn.bodies(); ++i)
                scale = std::max(scale, std::abs(y0[i]));
            m_floor = 1e-12 * scale;
        }
        return m_floor;
    }
    const double* y0;
    const double* y1;

private:
    static constexpr double unset = std::numeric_limits<double>::quiet_NaN();
    const Dynamics& m_dyn;
    double m_t0, m_t1;
    double m_ground0 = unset, m_ground1 = unset, m_floor = unset;
};

/// Whether a gap starts on the surface: a crossing from g0 at rate r0 would fall within
/// first_switch()'s margin (1e-9 of the step h).
bool on_surface(double g0, double r0, double h) {
    return std::abs(g0) <= 1e-9 * std::abs(r0) * h;
}

/// Whether a gap's rate changes sign between the ends of a step.
bool rate_turns(double r0, double r1) {
    return r0 * r1 < 0.0;
}

/// Whether gap j (value g0, rate r0 at the start of a step of length h) is closed just after
/// the start: its sign, or on the surface the sign of g0 + r0 d + a0 d^2 / 2 at d = h / 1000,
/// as the exact propagator chooses its configuration (where g = g' = 0, at rest at e_r = 0, the
/// acceleration decides).
bool closed_after_start(const Dynamics& dyn, int j, double g0, double r0, double h,
                        StepEnds& ends) {
    if (!on_surface(g0, r0, h)) return g0 > 0.0;
    const double d = 1e-3 * h;
    return g0 + r0 * d + 0.5 * dyn.gap_acceleration(j, ends.ground0(), ends.y0) * d * d > 0.0;
}

/// 1 if gap j may cross 0 inside a step, from its values and rates at the ends alone (a cheap
/// filter before crossing_in_step()), else 0: a sign change, a start on the surface that
/// leaves and may come back, or a turn whose reach - twice the bound from the end tangents, as
/// the peak scan of observers.cpp takes it - gets across. Written without branches so that
/// the loop over the gaps vectorises: it runs on every gap of every step.
double may_cross(double g0, double g1, double r0, double r1, double h) {
    const bool closed0 = g0 > 0.0;
    const bool sign_change = closed0 != (g1 > 0.0);
    const bool turns = rate_turns(r0, r1);
    const bool surface = on_surface(g0, r0, h);
    const bool dip = closed0 & (r0 < 0.0) & (std::min(g0, g1) - 0.5 * h * (r1 - r0) <= 0.0);
    const bool rise = !closed0 & (r0 > 0.0) & (std::max(g0, g1) + 0.5 * h * (r0 - r1) > 0.0);
    return sign_change | (turns & (surface | dip | rise)) ? 1.0 : 0.0;
}

/// Where, from the start of a step of length h, gap j (values g0, g1 and rates r0, r1 at its
/// ends) first crosses 0 on the quintic Hermite interpolant; nothing if it does not.
/// Beyond a sign change between the ends, two crossings inside one step count:
/// - a graze, a gap on one side at both ends that touches the other inside: a body that comes
///   slowly while pulled away penetrates briefly, bounded by no contact period, so no step
///   length rules it out (the exact propagator's interval, a quarter of the shortest contact
///   period, missed 3 of 36 impacts per period at the wall of Fig 4's row at fc 1000,
///   e_r 0.125, f_r 0.1: F_m 2 % off). It shows as a rate that turns and a turning point on
///   the other side.
/// - a step that starts on the surface (a switch ended the step before, so g0 is 0 to
///   round-off and its sign says nothing) leaves it on the side its rate points to, as the
///   exact propagator's configuration does, and may come back across before the step ends.
/// Gaps are penetrations here: positive is closed. Not found: two turns of the interpolant
/// inside one step (a start on a switch that leaves, comes back and leaves again; a graze and
/// a sign change in the same step, where the root found may be the later one), rare at these
/// step lengths.
std::optional<double> crossing_in_step(const Dynamics& dyn, int j, double g0, double g1, double r0,
                                       double r1, double h, StepEnds& ends) {
    const bool surface = on_surface(g0, r0, h);
    const bool closed1 = g1 > 0.0;
    const bool turns = rate_turns(r0, r1);
    const double a0 = dyn.gap_acceleration(j, ends.ground0(), ends.y0);
    const bool closed0 = closed_after_start(dyn, j, g0, r0, h, ends);
    if (closed0 == closed1 && (surface || !turns)) return std::nullopt;
    const detail::QuinticHermite g(g0, r0, a0, g1, r1,
                                   dyn.gap_acceleration(j, ends.ground1(), ends.y1), h);
    // From the surface, the gap first goes where it points, then comes back across: the
    // crossing lies beyond its turn (a start with no rate, at rest at e_r = 0, has no turn to
    // bracket from: the sign change from g0 finds it).
    const auto sign_change = [&]() -> std::optional<double> {
        if ((g0 > 0.0) == closed1) return std::nullopt;
        return g.crossing(0.0, 0.0, h);
    };
    if (closed0 != closed1 && !(surface && turns)) return sign_change();
    const double turn = g.stationary_point(0.0, h);
    const double at_turn = g.value(turn);
    if (surface) {
        if ((at_turn > 0.0) != closed0 || std::abs(at_turn) <= ends.floor()) return sign_change();
        return g.crossing(0.0, turn, h);
    }
    // A graze: same side at both ends, the turn beyond the surface.
    if ((at_turn > 0.0) == closed0 || std::abs(at_turn) <= ends.floor()) return std::nullopt;
    return g.crossing(0.0, 0.0, turn);
}

/// Earliest time in (t0 + margin, t1 - margin) at which a contact opens or closes during the
/// step y0 -> y1 (crossing_in_step()) ({t1, -1} if none). at0 holds the gaps at y0; at1
/// receives those at y1.
Switch first_switch(const Dynamics& dyn, double t0, double t1, const double* y0, const double* y1,
                    const GapState& at0, GapState& at1) {
    const double h = t1 - t0;
    const double margin = 1e-9 * h;
    Switch first{t1, -1};
    StepEnds ends(dyn, t0, t1, y0, y1);
    at1.of(dyn, y1);
    const int gaps = dyn.gaps();
    double* candidate = at1.candidate.data();
    for (int j = 0; j < gaps; ++j)
        candidate[j] = may_cross(at0.value[j], at1.value[j], at0.rate[j], at1.rate[j], h);
    for (int j = 0; j < gaps; ++j) {
        if (candidate[j] == 0.0) continue;
        const double g0 = at0.value[j], g1 = at1.value[j];
        const double r0 = at0.rate[j], r1 = at1.rate[j];
        const std::optional<double> tau = crossing_in_step(dyn, j, g0, g1, r0, r1, h, ends);
        if (!tau) continue;
        const double t = t0 + *tau;
        if (t > t0 + margin && t < t1 - margin && t < first.t) first = {t, j};
    }
    return first;
}

/// Newton iterations on the stepper's dense output of the step just taken, for schemes that
/// have one (exact): the switch time to round-off instead of the interpolant's accuracy.
double refine_switch(const Dynamics& dyn, const Stepper& stepper, Switch s, double t0, double t1,
                     std::vector<double>& scratch) {
    const int n = dyn.bodies();
    const double margin = 1e-9 * (t1 - t0);
    double t = s.t;
    for (int it = 0; it < 8; ++it) {
        if (!stepper.dense_state(t, scratch.data())) return s.t;
        const double rate = dyn.gap_rate(s.gap, scratch.data() + n);
        if (rate == 0.0) break;
        const double dt = -dyn.gap(s.gap, scratch.data()) / rate;
        t = std::clamp(t + dt, t0 + margin, t1 - margin);
        if (std::abs(dt) <= 1e-14 * (1.0 + std::abs(t))) break;
    }
    return t;
}

/// The first switch of a step on a stepper with dense output, given s, the one first_switch()
/// found and refine_switch() placed at t1: another gap whose side at t1 differs from its side
/// at t0 crossed before t1, and the earliest such crossing is the switch (bisection on the
/// dense output, then refine_switch()). first_switch() orders the crossings by where the
/// interpolant puts them, and the interpolant spans the kink of the first switch: on Fig 13's
/// row at f_r = 2.4088 a contact that closed 1.9e-4 before another opened (a step of 0.022)
/// was placed after it, closed late, and the orbit's F_m came out 7.7e-6 off (rk8pd and rkf45
/// agreed to 1e-12). Up to the first switch the dense output is the flow itself, so a gap
/// that has changed sides by t1 on it did cross first.
double earliest_switch(const Dynamics& dyn, const Stepper& stepper, Switch s, double t0,
                       double t_end, const GapState& at0, StepEnds& ends,
                       std::vector<double>& scratch) {
    const double h = t_end - t0;
    if (!stepper.dense_state(s.t, scratch.data())) return s.t;
    for (int j = 0; j < dyn.gaps(); ++j) {
        if (j == s.gap) continue;
        // The side the configuration took at the start; a side change within the noise floor
        // (bodies in lockstep at e_r = 0) is none.
        const bool closed0 = closed_after_start(dyn, j, at0.value[j], at0.rate[j], h, ends);
        const double g1 = dyn.gap(j, scratch.data());
        if ((g1 > 0.0) == closed0 || std::abs(g1) <= ends.floor()) continue;
        double lo = t0, hi = s.t;
        for (int it = 0; it < 60 && hi - lo > 1e-9 * h; ++it) {
            const double mid = 0.5 * (lo + hi);
            stepper.dense_state(mid, scratch.data());
            ((dyn.gap(j, scratch.data()) > 0.0) == closed0 ? lo : hi) = mid;
        }
        // Newton from the bracket's end may leave it at a near-tangential crossing: the
        // bracket's end is then kept.
        const double refined = refine_switch(dyn, stepper, {hi, j}, t0, t_end, scratch);
        const double slack = 1e-9 * h;
        s = {refined >= lo - slack && refined <= hi + slack ? refined : hi, j};
        stepper.dense_state(s.t, scratch.data());
    }
    return s.t;
}

/// Throws std::invalid_argument on a span, plan or state run() cannot take.
void check_run_arguments(const Dynamics& dyn, const StepPlan& plan, const RunSpan& span,
                         const std::vector<double>& y) {
    detail::require_range("run.periods", static_cast<double>(span.periods), 1.0, 1e9);
    if (span.transient_periods < 0 || span.transient_periods >= span.periods)
        throw std::invalid_argument("run.transient_periods: must be in [0, periods - 1], got " +
                                    std::to_string(span.transient_periods));
    if (span.first_period < 0 || span.first_period >= span.periods)
        throw std::invalid_argument("run: the first period must be in [0, periods - 1], got " +
                                    std::to_string(span.first_period));
    detail::require_length("initial state", y.size(), static_cast<std::size_t>(dyn.dimension()));
    if (plan.steps_per_period < 1 || !(plan.step > 0.0))
        throw std::invalid_argument("run: the step plan is empty (steps_per_period < 1)");
}

/// The steps of a run: advances the state over one step of the plan at a time, in pieces
/// that end on contact switches, and feeds every piece to the observers. Owns the buffers the
/// steps reuse, so that a step allocates nothing.
class StepSequence {
public:
    /// keep_going (may be empty) is asked every ask_every pieces: false stops the sequence.
    StepSequence(const Dynamics& dyn, Stepper& stepper, const StepPlan& plan,
                 std::vector<double>& y, std::span<Observer* const> observers,
                 std::function<bool()> keep_going, long ask_every)
        : m_dyn(dyn), m_stepper(stepper), m_plan(plan), m_y(y), m_observers(observers),
          m_y_prev(y.size()), m_gaps(dyn), m_gaps_next(dyn), m_scratch(y.size()),
          m_keep_going(std::move(keep_going)), m_ask_every(ask_every) {
        m_gaps.of(dyn, y.data());
    }
    /// Advances the state from t0 to t_end (one step of the plan in forcing period `period`);
    /// returns the number of pieces taken. Stops early, mid-step, once keep_going said false.
    long advance(double t0, double t_end, long period, bool recording);
    /// Whether keep_going stopped the sequence.
    [[nodiscard]] bool stopped() const { return m_stopped; }
    /// Tells every observer that forcing period n ended at t; true if one asks to stop.
    bool end_period(long n, double t) const;

private:
    double take_piece(double t0, double t_end, bool may_split);

    const Dynamics& m_dyn;
    Stepper& m_stepper;
    const StepPlan& m_plan;
    std::vector<double>& m_y;
    std::span<Observer* const> m_observers;
    std::vector<double> m_y_prev;
    // Gaps at the current state, carried from step to step so each is computed once.
    GapState m_gaps, m_gaps_next;
    std::vector<double> m_scratch;
    std::function<bool()> m_keep_going;
    long m_ask_every;
    long m_pieces_since_ask = 0;
    bool m_stopped = false;
};

long StepSequence::advance(double t0, double t_end, long period, bool recording) {
    // A contact switch inside a step puts a kink in the force, which costs a fourth-order
    // scheme two orders; so a step that straddles a switch is redone in pieces that end on it.
    // Bounded: each piece passes at least one switch.
    long pieces = 0;
    for (int piece = 0; piece <= 2 * m_dyn.gaps() && t0 < t_end; ++piece) {
        const double t1 = take_piece(t0, t_end, piece < 2 * m_dyn.gaps());
        const StepView view{t0, t1, m_y_prev.data(), m_y.data(), period, recording, &m_stepper};
        for (Observer* o : m_observers)
            o->on_step(view);
        ++pieces;
        t0 = t1;
        // Asked per piece, not per step: a step of a long row that many switches split can
        // take seconds (each piece is a whole step of every body).
        if (m_keep_going && ++m_pieces_since_ask >= m_ask_every) {
            m_pieces_since_ask = 0;
            if (!m_keep_going()) {
                m_stopped = true;
                break;
            }
        }
    }
    return pieces;
}

/// Steps the state from t0 towards t_end, ending on the first contact switch instead when
/// may_split and the plan splits at switches; returns where the piece ended.
double StepSequence::take_piece(double t0, double t_end, bool may_split) {
    std::copy(m_y.begin(), m_y.end(), m_y_prev.begin());
    m_stepper.step(t0, t_end - t0, m_y);
    double t1 = t_end;
    if (m_plan.split_at_switches && may_split) {
        const Switch s =
            first_switch(m_dyn, t0, t_end, m_y_prev.data(), m_y.data(), m_gaps, m_gaps_next);
        if (s.gap >= 0) {
            StepEnds ends(m_dyn, t0, t_end, m_y_prev.data(), m_y.data());
            t1 = earliest_switch(m_dyn, m_stepper,
                                 {refine_switch(m_dyn, m_stepper, s, t0, t_end, m_scratch), s.gap},
                                 t0, t_end, m_gaps, ends, m_scratch);
        }
        if (t1 < t_end) {
            std::copy(m_y_prev.begin(), m_y_prev.end(), m_y.begin());
            m_stepper.reset();
            m_stepper.step(t0, t1 - t0, m_y);
            m_stepper.reset();
            m_gaps_next.of(m_dyn, m_y.data());
        }
        std::swap(m_gaps, m_gaps_next);
    } else if (m_plan.split_at_switches) {
        m_gaps.of(m_dyn, m_y.data());
    }
    // Without splitting, the gaps are not needed between steps.
    return t1;
}

bool StepSequence::end_period(long n, double t) const {
    // Every observer hears of the boundary, whatever the others answer.
    bool stop = false;
    for (Observer* o : m_observers)
        stop = o->on_period(n, t, m_y.data()) || stop;
    return stop;
}

std::string non_finite_message(double t_end, int body) {
    return "the state became non-finite before t = " + detail::format_number(t_end) + " (body " +
           std::to_string(body + 1) + "); the step or the parameters are out of the scheme's reach";
}

/// A long row is also asked inside a period, every ~2.6e5 body-pieces weighted by the observers'
/// step_cost() (~0.03 s), so that a cancel reaches a run whose single period takes seconds
/// (Nm = 1e6: 17 s, more with splits; a shooting of Nm = 150 with its tangent flow: 20 s).
long pieces_between_asks(int bodies, std::span<Observer* const> observers) {
    double cost = 1.0;
    for (const Observer* o : observers)
        cost += o->step_cost();
    return static_cast<long>(std::max(1.0, (1 << 18) / (bodies * cost)));
}

} // namespace

RunOutcome run(const Dynamics& dyn, Stepper& stepper, const StepPlan& plan, const RunSpan& span,
               std::vector<double>& y, std::span<Observer* const> observers,
               const ProgressCallback& progress) {
    check_run_arguments(dyn, plan, span, y);
    const int n = dyn.bodies();
    const int spp = plan.steps_per_period;
    const double h = plan.step;
    const long report_every = std::max(1L, span.periods / 200);
    RunOutcome out;
    out.scheme = plan.scheme;
    out.step = h;
    // Times are computed from integer step counts, so period boundaries never drift.
    auto time_at = [&](long period, int k) {
        return span.t_start + ((period - span.first_period) * spp + k) * h;
    };
    auto cancelled = [&](double fraction, double t) {
        if (!progress || progress(fraction)) return false;
        out.status = RunStatus::cancelled;
        out.message = "cancelled at t = " + detail::format_number(t);
        out.t_end = t;
        return true;
    };
    long p = span.first_period;
    int k = 0;
    std::function<bool()> keep_going;
    if (progress)
        keep_going = [&] {
            return !cancelled((p + static_cast<double>(k) / spp) / span.periods, time_at(p, k));
        };
    StepSequence steps(dyn, stepper, plan, y, observers, std::move(keep_going),
                       pieces_between_asks(n, observers));
    stepper.reset();

    if (span.first_period == 0) steps.end_period(0, span.t_start);
    out.periods_done = span.first_period;
    out.t_end = span.t_start;
    for (p = span.first_period; p < span.periods; ++p) {
        const bool recording = p >= span.transient_periods;
        for (k = 0; k < spp; ++k) {
            out.steps += steps.advance(time_at(p, k), time_at(p, k + 1), p, recording);
            if (steps.stopped()) return out;
        }
        out.periods_done = p + 1;
        out.t_end = time_at(p + 1, 0);
        if (const int body = first_non_finite_body(y, n); body >= 0) {
            out.status = RunStatus::non_finite;
            out.message = non_finite_message(out.t_end, body);
            return out;
        }
        if (steps.end_period(p + 1, out.t_end) && recording) {
            out.status = RunStatus::steady_state;
            return out;
        }
        if (((p + 1) % report_every == 0 || p + 1 == span.periods) &&
            cancelled(static_cast<double>(p + 1) / span.periods, out.t_end))
            return out;
    }
    return out;
}

void validate(const RunOptions& o) {
    detail::require_range("run.periods", static_cast<double>(o.periods), 1.0, 1e9);
    if (o.transient_periods != auto_transient &&
        (o.transient_periods < 0 || o.transient_periods >= o.periods))
        throw std::invalid_argument(
            "run.transient_periods: must be an integer in [0, periods - 1 = " +
            std::to_string(o.periods - 1) + "], got " + std::to_string(o.transient_periods));
    detail::require_range("run.tolerance", o.tolerance, 1e-12, 0.1);
    if (o.step) detail::require_range("run.step", *o.step, 0.0, 1e3, detail::Bound::open_low);
    detail::require_range("run.steady_tolerance", o.steady_tolerance, 0.0, 1.0,
                          detail::Bound::open_low);
    detail::require_range("run.max_steady_period", o.max_steady_period, 1, 1000);
    detail::require_range("run.max_work", o.max_work, 1.0, 1e15);
}

long default_transient_periods(const Dynamics& dyn, const RunOptions& options) {
    if (!dyn.ground_motion().is_harmonic()) return 0;
    const long cap = options.periods / 2;
    const auto& damping = dyn.chain().damping;
    const auto& spring = dyn.chain().spring;
    // MODEL.md §2 writes the decay rate as 2 pi eps, which holds below critical damping only:
    // beyond it the slow root k / (c/2 + sqrt(c^2/4 - k)) falls as 1 / eps (eps = 100: 0.0314,
    // not 628, so one discarded period left the creep of the start in the window).
    double slowest_decay = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < damping.size(); ++i) {
        const double half = damping[i] / 2.0;
        const double over = half * half - spring[i];
        slowest_decay =
            std::min(slowest_decay, over > 0.0 ? spring[i] / (half + std::sqrt(over)) : half);
    }
    if (!(slowest_decay > 0.0)) return cap;
    const double periods =
        std::ceil(dyn.ground_motion().f_r() * std::log(1.0 / options.tolerance) / slowest_decay);
    return std::min(cap, std::max(1L, static_cast<long>(std::min(periods, 1e9))));
}

long start_up_decay_periods(const Dynamics& dyn, double tolerance) {
    RunOptions uncapped;
    uncapped.tolerance = tolerance;
    uncapped.periods = 2'000'000'000; // the cap, periods / 2, is above the 1e9 ceiling
    return default_transient_periods(dyn, uncapped);
}

RunOptions with_transient_resolved(const Dynamics& dyn, RunOptions options) {
    if (options.transient_periods == auto_transient)
        options.transient_periods = default_transient_periods(dyn, options);
    return options;
}

StepPlan finer_plan(const Dynamics& dyn, const StepPlan& plan, double tolerance_divisor) {
    StepPlan finer = plan;
    // An adaptive scheme's steps end at each output time too: at a loose tolerance that
    // interval, not the error control, sets them, and a tighter tolerance alone left the steps
    // as they were. Its section points then agreed to 5e-11 where both were 2.4e-5 off (rkf45
    // at 0.1, Fig 13's row at f_r = 2.5, against exact at 1e-10; a reviewer's probe,
    // helper-75), as the simulator's comparison run found (comparison_plan()).
    if (traits(plan.scheme).adaptive)
        finer.tolerance = std::max(1e-12, plan.tolerance / tolerance_divisor);
    finer.steps_per_period = 2 * plan.steps_per_period;
    finer.step = dyn.period() / finer.steps_per_period;
    return finer;
}

StepPlan plan_run(const Dynamics& dyn, const RunOptions& options, int samples_per_period) {
    StepPlan plan = plan_step(dyn, options.scheme, options.tolerance, options.step);
    if (samples_per_period == 0) return plan;
    detail::require_range("samples per period", samples_per_period, 1, 10'000'000);
    plan.steps_per_period =
        (plan.steps_per_period + samples_per_period - 1) / samples_per_period * samples_per_period;
    plan.step = dyn.period() / plan.steps_per_period;
    return plan;
}

double contact_switches_per_period(const Dynamics& dyn) {
    return 2.0 * dyn.gaps() * dyn.period();
}

namespace {

/// Whether some body's own damping is critical (u'' = -k u - c u' with c^2 = 4 k, to 1e-9
/// relative; the chain's rates are per unit mass), so that its free motion has a double
/// eigenvalue and no eigenvector basis (exact_propagator.cpp).
bool critically_damped_body(const Chain& chain) {
    for (int i = 0; i < chain.bodies(); ++i) {
        const double c = chain.damping[i], four_k = 4.0 * chain.spring[i];
        if (std::abs(c * c - four_k) <= 1e-9 * four_k) return true;
    }
    return false;
}

/// Body-steps of one period's steps, and of one new configuration's set-up (0 but on exact).
std::pair<double, double> work_rates(const Dynamics& dyn, const StepPlan& plan, int tangents) {
    const double steps = static_cast<double>(plan.steps_per_period) * (1.0 + tangents);
    if (plan.scheme != Scheme::exact) return {static_cast<double>(dyn.bodies()) * steps, 0.0};
    // Calibrated on a 2-core machine (2026-11-27), on a row that finds new configurations
    // every period (Nm = 46, fc = 559, eps = 0.1, e_r = 0.22, f_r = 1): 1.44 s a period
    // (1.44e7 body-steps) where Nm x steps alone counted 6164; Nm = 20: 0.094 s. Half an n^3 a
    // configuration, 2 (Nm + 1) configurations a period, gives 3.7e7 and 1.4e6: above both.
    const double n = dyn.dimension();
    double per_period = std::max(static_cast<double>(dyn.bodies()), 0.08 * n * n) * steps;
    // Each contact switch splits a step (one more piece, a product per vector) and is located
    // by root finding on the propagator's dense states: about 100 body-steps, with about two
    // switches a contact per natural period (1 reduced time). Without it a 16-step plan (f_r
    // >= 1) was counted 3-5 times short: Fig 13's row, Nm 2 and 5 at f_r = 1, 3000 periods, ran
    // 0.13 s and 0.35 s, counted 0.026 s and 0.11 s (2026-11-27); f_r = 0.1 was counted right
    // by its 440 steps a period and is now 5 times over.
    const double switches = contact_switches_per_period(dyn);
    per_period += switches * (100.0 + (1.0 + tangents) * 0.08 * n * n);
    // A critically damped body makes every configuration it moves free in defective: each step
    // split at a switch, and each dense state, takes a matrix exponential. Measured on Fig 13's
    // row at f_r = 3 (300 periods, 2026-11-27), the time above eps = 0.999's, per period: Nm 5
    // 3.3e-4 s, 10 8.2e-4 s, 20 5.0e-3 s, 40 0.19 s (3.3e3 to 1.9e6 body-steps); 2 (Nm + 1)
    // exponentials of 250 + n^3 / 20 body-steps a period count 3.6e3, 1.4e4, 1.4e5, 2.1e6.
    // Calibrated at f_r = 3; a longer period has more switches (Nm 10, eps 1, f_r 0.3 ran 12.4 s
    // where 2 (Nm + 1) a period counted 9.4 s).
    if (critically_damped_body(dyn.chain()))
        per_period += std::max(2.0 * dyn.gaps(), switches) * (250.0 + 0.05 * n * n * n);
    return {per_period, 0.5 * n * n * n};
}

/// All 2^(Nm + 1) configurations of a row whose exact-propagator cache holds them (Nm <= 11),
/// else 0: no bound.
double cached_configurations(const Dynamics& dyn) {
    const double all = std::ldexp(1.0, std::min(dyn.gaps(), 1000));
    return all <= detail::exact_cache_capacity(dyn.dimension()) ? all : 0.0;
}

/// How many configurations `periods` periods may set up: 2 (Nm + 1) a period, at most all of a
/// row whose cache holds them.
double configurations(const Dynamics& dyn, double periods) {
    const double per_period = 2.0 * dyn.gaps() * periods;
    const double all = cached_configurations(dyn);
    return all > 0.0 ? std::min(per_period, all) : per_period;
}

} // namespace

double run_work(const Dynamics& dyn, const StepPlan& plan, double periods, int tangents) {
    const auto [steps, set_up] = work_rates(dyn, plan, tangents);
    return steps * periods + set_up * configurations(dyn, periods);
}

double affordable_periods(const Dynamics& dyn, const StepPlan& plan, double max_work) {
    // run_work() rises with the periods: 2 (Nm + 1) new configurations a period until a short
    // row has set up all of them, the steps alone after that.
    const auto [steps, set_up] = work_rates(dyn, plan, 0);
    const double per_gap_period = 2.0 * dyn.gaps();
    const double all = cached_configurations(dyn);
    double periods = max_work / (steps + set_up * per_gap_period);
    if (all > 0.0 && periods * per_gap_period > all) periods = (max_work - set_up * all) / steps;
    return std::max(0.0, std::floor(periods));
}

namespace {

const RunOptions& validated(const RunOptions& options) {
    validate(options);
    return options;
}

/// Refuses a run whose work (body-steps) exceeds options.max_work, with the estimate; `what`
/// says which run it is ("this run takes up to"), `remedy` leads the list of ways out.
const StepPlan& affordable(const Dynamics& dyn, const RunOptions& options, const StepPlan& plan,
                           const std::string& what = "this run takes up to",
                           const std::string& remedy = "") {
    const double work = run_work(dyn, plan, static_cast<double>(options.periods));
    detail::require_work(
        work, options.max_work, what,
        "Nm " + std::to_string(dyn.bodies()) + " x " + std::to_string(plan.steps_per_period) +
            " steps per forcing period" +
            // Short: the tools cut a message past 1000 characters (the periods and the limit
            // were cut from exact's).
            (plan.scheme == Scheme::exact
                 ? std::string(" (exact: (2 Nm)^2 a step, a switch, (2 Nm)^3 / 2 a new contact "
                               "configuration") +
                       (critically_damped_body(dyn.chain())
                            ? ", a matrix exponential a switch: critical damping)"
                            : ")")
                 : std::string()) +
            " x " + std::to_string(options.periods) + " periods",
        // A tool whose runs take their periods from a flag names it in place of the key.
        remedy + "fewer periods (run.periods), a higher forcing frequency (excitation.f_r), or a "
                 "larger run.max_work");
    return plan;
}

} // namespace

void require_affordable(const Dynamics& dyn, const RunOptions& options) {
    (void)affordable(dyn, options, plan_run(dyn, validated(options)));
}

void require_affordable(const Dynamics& dyn, const RunOptions& options, const StepPlan& plan,
                        const std::string& what, const std::string& remedy) {
    (void)affordable(dyn, validated(options), plan, what, remedy);
}

PlannedRun::PlannedRun(const Dynamics& dyn, const RunOptions& options,
                       const std::vector<double>& initial, int samples_per_period)
    : PlannedRun(dyn, options, plan_run(dyn, validated(options), samples_per_period), initial) {}

PlannedRun::PlannedRun(const Dynamics& dyn, const RunOptions& options, const StepPlan& plan,
                       const std::vector<double>& initial)
    : m_dyn(dyn), m_span{validated(options).periods,
                         with_transient_resolved(dyn, options).transient_periods, 0.0},
      m_plan(affordable(dyn, options, plan)), m_stepper(make_stepper(plan, dyn)),
      m_state(initial_state(dyn, initial)) {}

RunOutcome PlannedRun::run(std::span<Observer* const> observers, const ProgressCallback& progress) {
    return run(m_span, observers, progress);
}

RunOutcome PlannedRun::run(const RunSpan& span, std::span<Observer* const> observers,
                           const ProgressCallback& progress) {
    return gapchain::run(m_dyn, *m_stepper, m_plan, span, m_state, observers, progress);
}

} // namespace gapchain
