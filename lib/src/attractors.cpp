#include "gapchain/attractors.hpp"
#include "gapchain/grid.hpp"

#include "gapchain/poincare.hpp"

#include "gapchain/bounds.hpp"
#include "gapchain/lyapunov.hpp"
#include "gapchain/observers.hpp"
#include "gapchain/orbit.hpp"
#include "gapchain/simulation.hpp"

#include "detail/attractor_search.hpp"
#include "detail/check.hpp"
#include "detail/parallel.hpp"
#include "detail/random.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace gapchain {

using detail::clouds_overlap;
using detail::search_row_error;
using detail::state_scale;
using detail::StateScale;

void validate(const AttractorOptions& o, int Nm) {
    detail::require_count("samples", o.samples, 1, 10'000'000);
    // The tools read seeds as signed 64-bit integers: one range for them and Python.
    if (o.seed > (std::uint64_t{1} << 62))
        throw std::invalid_argument("seed: must be an integer in [0, 2^62 = 4611686018427387904], "
                                    "got " +
                                    std::to_string(o.seed));
    detail::require_range("box", o.box, 1e-9, 100.0);
    detail::require_range("section_points", o.section_points, 20, 100000);
    detail::require_range("overlap_factor", o.overlap_factor, 1.0, 100.0);
    detail::require_range("lyapunov_periods", static_cast<double>(o.lyapunov_periods), 10.0, 1e6);
    detail::require_range("chaos_threshold", o.chaos_threshold, 0.0, 1e3);
    detail::require_range("threads", o.threads, 0, 4096);
    validate(o.run);
    if (!o.center.empty()) {
        if (o.center.size() != static_cast<std::size_t>(2 * Nm))
            throw std::invalid_argument("center: must have 2 Nm = " + std::to_string(2 * Nm) +
                                        " entries (u then v) or none (rest), got " +
                                        std::to_string(o.center.size()));
        for (std::size_t i = 0; i < o.center.size(); ++i)
            detail::require_range("center[" + std::to_string(i) + "]", o.center[i], -1e9, 1e9);
    }
    if (o.slice) {
        detail::require_range("slice.first", o.slice->first, 0, 2 * Nm - 1);
        detail::require_range("slice.second", o.slice->second, 0, 2 * Nm - 1);
        detail::require_range("slice.resolution", o.slice->resolution, 2, 2000);
        if (o.slice->first == o.slice->second)
            throw std::invalid_argument("slice: the two state variables must differ, got " +
                                        std::to_string(o.slice->first) + " twice");
    }
}

std::vector<double> box_center(const AttractorOptions& options, int Nm) {
    return options.center.empty() ? std::vector<double>(static_cast<std::size_t>(2 * Nm), 0.0)
                                  : options.center;
}

BasinSlice basin_slice(std::string_view first, std::string_view second, int Nm, int resolution) {
    const auto index = [Nm](std::string_view name) {
        const std::invalid_argument bad("grid: expected u1..u" + std::to_string(Nm) + " or v1..v" +
                                        std::to_string(Nm) + ", got \"" + std::string(name) + "\"");
        SectionVariable v;
        try {
            v = SectionVariable::parse(name, Nm, "grid");
        } catch (const std::invalid_argument&) {
            throw bad;
        }
        using K = SectionVariable::Kind;
        if (v.kind != K::displacement && v.kind != K::velocity) throw bad;
        return (v.kind == K::velocity ? Nm : 0) + v.index;
    };
    const int x = index(first), y = index(second);
    if (x == y)
        throw std::invalid_argument("grid: two different state variables, got \"" +
                                    std::string(first) + "\" twice");
    return BasinSlice{x, y, resolution};
}

std::string_view regime_label(const Attractor& a) {
    return a.settled ? to_string(a.regime) : std::string_view("unsettled");
}

StateScale detail::state_scale(const ReducedParameters& p) {
    const double A = single_body_amplitude(p.f_r, p.eps);
    return {A, 2.0 * std::numbers::pi * p.f_r * A, p.Nm};
}

std::optional<std::string> detail::search_row_error(const ReducedParameters& p) {
    // Without damping the flow keeps phase-space volume: nothing attracts, and every start
    // would be reported as an attractor of its own.
    if (!(p.eps > 0.0))
        return "model.eps: an attractor search needs damping, eps > 0 (a row without it has no "
               "attractors), got " +
               detail::format_number(p.eps);
    return std::nullopt;
}

namespace {

/// Members of a non-periodic group continued first to test it: a sixteenth of the random starts,
/// 3 to 8 (and at most its members). If its starts leave it at a share q within the
/// continuation, none of n does with odds (1 - q)^n (Fig 13's row at f_r = 2.05, 300-period
/// runs continued 3000: q = 0.42; 1.3 % for 8, 20 % for 3; a single probe missed it at 10
/// starts, seed 4). The cap keeps the test's cost within about 0.6 of the search's at ten run
/// lengths; the floor of 3 probes at up to 10 run lengths each costs a search of 10 starts up to
/// three times their work, and fewer starts more (6 times at 5).
std::size_t probe_count(long random_starts, std::size_t members) {
    return std::min<std::size_t>(members, std::clamp<long>(random_starts / 16, 3, 8));
}

/// The body-steps of a search with every start run to its full length (settled starts stop
/// sooner), and what they are made of.
struct SearchWork {
    double body_steps = 0.0;
    std::string breakdown;
};

SearchWork search_work(const Dynamics& dyn, const StepPlan& plan, const AttractorOptions& options) {
    // run.max_work bounds the starts of the search, as it bounds a Lyapunov run with its tangent
    // vectors: 1e7 starts of 20,000 periods were accepted and ran for years. It also counts what
    // one non-periodic group adds: its confirmation (up to ten run lengths for each member
    // probe_count() continues) and its lambda_max run with one tangent vector. A single start of Nm
    // = 20,000 passed with 2.3 s estimated, ran 24 s and was then refused for that tangent run.
    // Further groups' runs are held to it one by one (confirmation_periods(), chain_lyapunov()):
    // their number is not known before.
    const double starts =
        static_cast<double>(options.samples) +
        (options.slice ? std::pow(static_cast<double>(options.slice->resolution), 2.0) : 0.0);
    RunOptions tangent = options.run;
    tangent.periods = options.lyapunov_periods;
    const StepPlan tangent_plan = plan_run(dyn, tangent_run_options(dyn, tangent));
    const long tangent_steps = tangent_plan.steps_per_period;
    const auto probes = static_cast<double>(
        probe_count(options.samples, static_cast<std::size_t>(options.samples)));
    const double body_steps =
        run_work(dyn, plan, static_cast<double>(options.run.periods)) * (starts + 10.0 * probes) +
        run_work(dyn, tangent_plan, static_cast<double>(options.lyapunov_periods), 1);
    std::ostringstream breakdown;
    breakdown << "(" << detail::format_number(starts) << " starts + up to 10 x " << probes
              << " to confirm a non-periodic group) x " << options.run.periods << " periods x Nm "
              << dyn.bodies() << " x " << plan.steps_per_period
              << " steps per forcing period, + 2 x " << options.lyapunov_periods
              << " periods x Nm x " << tangent_steps
              << " for its lambda_max run with a tangent vector";
    return {body_steps, breakdown.str()};
}

} // namespace

void validate(const ReducedParameters& p, const AttractorOptions& options) {
    validate(p);
    validate(options, p.Nm);
    if (const auto error = search_row_error(p)) throw std::invalid_argument(*error);
    // Periodic attractors are found where a run stops on its steady state; without the stop
    // every orbit reads as unsettled and one orbit can split into several groups.
    if (!options.run.stop_at_steady_state)
        throw std::invalid_argument("run.steady_state: an attractor search needs it true (its "
                                    "periodic attractors are the runs that settle), got false");
    // The scheme must take the row (exact refuses the stiffest contacts): refused here, before
    // a line of values (every one validated first) runs any.
    const Dynamics dyn = Dynamics::paper_row(p);
    const StepPlan plan = plan_run(dyn, options.run);
    const SearchWork work = search_work(dyn, plan, options);
    detail::require_work(
        work.body_steps, options.run.max_work, "this search runs up to", work.breakdown,
        std::string("fewer starts, ") + (options.slice ? "a coarser slice, " : "") +
            "shorter runs (run.periods), or raise run.max_work");
    // A box narrower than 1e-12 of its center's entry draws starts a few doubles apart (around
    // 1e9, 1e-9 A is below one double's spacing): the fractions would count the same start
    // many times.
    const StateScale scale = state_scale(p);
    for (std::size_t i = 0; i < options.center.size(); ++i) {
        const double half = options.box * scale.of(static_cast<int>(i));
        if (half < 1e-12 * std::abs(options.center[i]))
            throw std::invalid_argument(
                "box: half-width " + detail::format_number(half) + " is below 1e-12 of center[" +
                std::to_string(i) + "] = " + detail::format_number(options.center[i]) +
                ": the starts would not differ; move the center nearer rest, or raise box to at "
                "least " +
                detail::format_number(1e-12 * std::abs(options.center[i]) / half * options.box));
    }
    const RunOptions run = with_transient_resolved(dyn, options.run);
    const long window = run.periods - run.transient_periods;
    if (window < 20)
        throw std::invalid_argument(
            "run.periods: an attractor search records at least 20 periods of each run (its "
            "section points), got run.periods - run.transient_periods = " +
            std::to_string(window) + "; raise run.periods");
}

namespace {

using Points = std::vector<std::vector<double>>;

/// Share of a cloud's diameter within which two clouds count as one: a torus or a chaotic set
/// sampled over two windows can leave gaps between the windows' points (slow drift along a
/// nearly resonant torus, intermittency) far larger than the point spacing, but not a tenth of
/// its size; attractors this close are not told apart.
constexpr double coarse_resolution = 0.05;

/// Keeps the states at the last `capacity` period ends of the recorded window.
class SectionRing final : public Observer {
public:
    explicit SectionRing(std::size_t capacity) : m_capacity(capacity) {}
    void on_step(const StepView& step) override { m_recording = step.recording; }
    bool on_period(long n, double, const double* y) override {
        if (n == 0 || !m_recording) return false;
        m_points.emplace_back(y, y + m_dimension);
        if (m_points.size() > m_capacity) m_points.pop_front();
        return false;
    }
    void set_dimension(int dimension) { m_dimension = dimension; }
    [[nodiscard]] Points points() const { return {m_points.begin(), m_points.end()}; }

private:
    std::size_t m_capacity;
    int m_dimension = 0;
    bool m_recording = false;
    std::deque<std::vector<double>> m_points;
};

/// max_i |a_i - b_i| / scale_i.
double scaled_distance(const std::vector<double>& a, const std::vector<double>& b,
                       const StateScale& scale) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
        d = std::max(d, std::abs(a[i] - b[i]) / scale.of(static_cast<int>(i)));
    return d;
}

/// What one start's run ended on.
struct StartOutcome {
    bool failed = false;
    bool periodic = false;
    int period = 0;
    bool newton = false;
    double max_multiplier = 0.0;
    double max_multiplier_error = 0.0;
    double F_m = 0.0;     // the orbit's (Newton) or the run's
    double run_F_m = 0.0; // over the run's recorded window
    double spread = 0.0;  // the run's F_m_error
    // A Newton orbit's state error (absolute), estimated as |P(x) - x| / (1 - |mu|): the bound
    // for a contraction whose monodromy is normal, mu its largest multiplier (a row with
    // contacts has a non-normal one, so an estimate; matching allows ten times it).
    double newton_accuracy = 0.0;
    long settle_period = -1;   // the run's cycle_entry_period (-1: did not settle)
    long last_far = -1;        // the run's last_far_period
    long periods_run = 0;      // its runs' periods, continuations (extend()) included
    std::vector<double> state; // on the attractor at phase 0
    Points section;            // the orbit's points, or the run's last ones
};

/// Puts a converged Newton orbit into s: minimal period, multipliers, F_m, state, points and
/// the state error that matching allows for.
void take_orbit(const PeriodicOrbit& found, StartOutcome& s) {
    s.newton = true;
    s.period = found.minimal_period;
    s.max_multiplier = found.max_multiplier;
    s.max_multiplier_error = found.max_multiplier_error;
    double size = 0.0; // |x|, the Euclidean norm of the residual's scale
    for (const double x : found.state)
        size += x * x;
    size = std::sqrt(size);
    s.newton_accuracy = found.max_multiplier < 1.0
                            ? found.residual * (1.0 + size) / (1.0 - found.max_multiplier)
                            : 0.0;
    s.F_m = found.F_m;
    s.state = found.state;
    s.section = found.period_ends;
}

RunOptions start_run_options(const RunOptions& search) {
    RunOptions run = search;
    run.multistability_check = false;
    run.estimate_error = true;
    return run;
}

/// A run of the search and its last section points.
struct RecordedRun {
    SimulationResult result;
    Points section;
};

RecordedRun run_recorded(const Dynamics& dyn, const RunOptions& run, std::size_t section_points,
                         const std::vector<double>& start, const ProgressCallback& keep_going) {
    SectionRing ring(section_points);
    ring.set_dimension(dyn.dimension());
    SimulationHooks hooks;
    hooks.observers.push_back(&ring);
    hooks.progress = keep_going;
    RecordedRun recorded{simulate(dyn, run, start, hooks), {}};
    recorded.section = ring.points();
    return recorded;
}

/// A start's run. One that did not settle but whose states repeat with a lag beyond
/// run.max_steady_period (SimulationResult::longer_cycle_period) is run again with the steady-state
/// test trying cycles up to that lag, so that it settles, and is confirmed, as any other start
/// does: the Nm = 5 row at fc = 10, eps = 0.1, e_r = 0.06, f_r = 1.6 (a point of the Tables 2-3
/// subset) sends 7 of 8 starts to period-18 orbits of F_m 1.65828; read as two groups still
/// converging, they were left out of the design value, which was the period-1 orbit's 1.47504.
StartOutcome run_start(const Dynamics& dyn, const AttractorOptions& o,
                       const std::vector<double>& start, const ProgressCallback& keep_going) {
    RunOptions run = start_run_options(o.run);
    const auto section_points = static_cast<std::size_t>(o.section_points);
    RecordedRun recorded = run_recorded(dyn, run, section_points, start, keep_going);
    StartOutcome s;
    if (recorded.result.status == RunStatus::non_finite ||
        recorded.result.status == RunStatus::cancelled) {
        s.failed = true;
        return s;
    }
    if (const std::optional<int> lag = recorded.result.longer_cycle_period) {
        run.max_steady_period = *lag;
        RecordedRun again = run_recorded(dyn, run, section_points, start, keep_going);
        if (again.result.steady_state_period) recorded = std::move(again);
    }
    const SimulationResult& r = recorded.result;
    s.run_F_m = s.F_m = r.F_m;
    s.spread = r.F_m_error;
    s.state = r.final_state;
    s.section = std::move(recorded.section);
    s.last_far = r.last_far_period;
    s.periods_run = r.periods_simulated;
    if (!r.steady_state_period) return s;
    s.periodic = true;
    s.period = *r.steady_state_period;
    s.settle_period = r.cycle_entry_period;
    // The steady state's own largest force, not a transient's (replaced by Newton's below).
    if (r.F_m_orbit) s.F_m = *r.F_m_orbit;
    // Newton shoots on the exact scheme; a row it refuses (fc above ~1.27e8, Nm > 64) keeps
    // the run's orbit unconfirmed rather than failing the whole search after its runs.
    // So does one whose shooting exceeds run.max_work.
    const auto found = confirm_periodic_orbit(dyn, s.period, r.final_state, o.run.max_work);
    if (found && found->status == OrbitStatus::converged) {
        take_orbit(*found, s);
        return s;
    }
    const auto k = static_cast<std::ptrdiff_t>(std::min<std::size_t>(s.period, s.section.size()));
    s.section.erase(s.section.begin(), s.section.end() - k);
    return s;
}

/// Whether two periodic orbits pass through the same points: each one's first point within
/// tolerance of one of the other's.
bool same_orbit(const Points& a, const Points& b, const StateScale& scale, double tolerance) {
    if (a.empty() || b.empty()) return false;
    const auto near = [&](const std::vector<double>& x, const Points& cloud) {
        return std::any_of(cloud.begin(), cloud.end(), [&](const std::vector<double>& y) {
            return scaled_distance(x, y, scale) <= tolerance;
        });
    };
    return near(a.front(), b) && near(b.front(), a);
}

/// Median over a's points of the distance to the nearest point of b (skipping the point itself
/// when a and b are the same cloud).
double median_nearest(const Points& a, const Points& b, const StateScale& scale, bool same) {
    std::vector<double> nearest;
    nearest.reserve(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t j = 0; j < b.size(); ++j)
            if (!same || i != j) best = std::min(best, scaled_distance(a[i], b[j], scale));
        nearest.push_back(best);
    }
    auto mid = nearest.begin() + static_cast<std::ptrdiff_t>(nearest.size() / 2);
    std::nth_element(nearest.begin(), mid, nearest.end());
    return *mid;
}

/// Largest distance between two points of a cloud (scaled).
double diameter(const Points& a, const StateScale& scale) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = i + 1; j < a.size(); ++j)
            d = std::max(d, scaled_distance(a[i], a[j], scale));
    return d;
}

} // namespace

bool detail::clouds_overlap(const Points& a, const Points& b, const StateScale& scale,
                            double factor) {
    if (a.size() < 2 || b.size() < 2) return false;
    const double inner =
        std::max(median_nearest(a, a, scale, true), median_nearest(b, b, scale, true));
    const double size = std::max(diameter(a, scale), diameter(b, scale));
    const double limit = std::max(factor * inner, coarse_resolution * size);
    return median_nearest(a, b, scale, false) <= limit &&
           median_nearest(b, a, scale, false) <= limit;
}

namespace {

/// A run that ends this close (scaled) to a stable orbit's point is in its linear neighbourhood
/// and converging to it, however slowly (Fig 13's line at f_r = 3.2: a period-15 orbit with
/// |mu| = 0.94 takes thousands of periods to reach the steady-state test's 1e-10).
constexpr double converging_distance = 1e-2;

/// Whether a run that did not settle ended close to the stable periodic attractor a.
bool converging_to(const StartOutcome& s, const Attractor& a, const StateScale& scale) {
    if (a.period == 0 || a.max_multiplier >= 1.0 || s.state.empty()) return false;
    for (const auto& x : a.section)
        if (scaled_distance(s.state, x, scale) <= converging_distance) return true;
    return false;
}

/// Whether two sample maxima of F_m can come from one attractor: within three times the larger
/// of their sampling spreads (and 1e-3 relative, for windows that barely spread).
bool forces_agree(const StartOutcome& s, const StartOutcome& representative) {
    const double spread = std::max(s.spread, representative.spread);
    return std::abs(s.F_m - representative.F_m) <=
           3.0 * spread + 1e-3 * std::max(s.F_m, representative.F_m);
}

/// Whether s reached attractor a, whose first member was `representative`. Two Newton orbits
/// with equal minimal periods match to 1e-6, or to ten times their state error estimates where
/// those are larger (at most converging_distance): Newton stops at a residual of 1e-9, which a
/// slowly contracting orbit leaves 1 / (1 - |mu|) times larger in the state (an overdamped row,
/// eps = 100, |mu| = 0.969, A = 0.005: its orbit was found twice, 1.2e-6 A apart); a steady state
/// Newton did not confirm is the run's discrete orbit, off the exact one by the run's truncation
/// error, and its detected period may be a multiple of the minimal one: it matches to 10 x the
/// run's tolerance, with either period dividing the other.
bool belongs(const StartOutcome& s, const Attractor& a, const StartOutcome& representative,
             const StateScale& scale, const AttractorOptions& o) {
    if (s.periodic && a.period != 0) {
        if (s.newton && a.newton_confirmed) {
            const double bound =
                (s.newton_accuracy + representative.newton_accuracy) / std::min(scale.u, scale.v);
            return a.period == s.period &&
                   same_orbit(a.section, s.section, scale,
                              std::clamp(10.0 * bound, 1e-6, converging_distance));
        }
        return (a.period % s.period == 0 || s.period % a.period == 0) &&
               same_orbit(a.section, s.section, scale, 10.0 * o.run.tolerance);
    }
    if (s.periodic) return false;
    if (a.period != 0) return converging_to(s, a, scale);
    return forces_agree(s, representative) &&
           clouds_overlap(a.section, s.section, scale, o.overlap_factor);
}

Attractor new_attractor(const StartOutcome& s, const std::vector<double>& start, int id) {
    Attractor a;
    a.id = id;
    a.period = s.periodic ? s.period : 0;
    a.newton_confirmed = s.newton;
    a.max_multiplier = s.max_multiplier;
    a.max_multiplier_error = s.max_multiplier_error;
    a.F_m = s.F_m;
    // A confirmed orbit's error is set in characterise(); an unconfirmed one keeps its run's.
    a.F_m_error = s.periodic && s.newton ? std::abs(s.F_m - s.run_F_m) : s.spread;
    a.initial_state = start;
    a.state = s.state;
    a.section = s.section;
    return a;
}

/// A non-periodic attractor's F_m is the largest of its members' sample maxima, with that
/// member's sampling spread.
void add_member(Attractor& a, const StartOutcome& s) {
    if (a.period != 0 || s.F_m <= a.F_m) return;
    a.F_m = s.F_m;
    a.F_m_error = s.spread;
}

/// Which pass of group_outcomes() takes an outcome: Newton orbits, other steady states, then
/// runs that did not settle.
int grouping_pass(const StartOutcome& s) {
    return s.periodic ? (s.newton ? 0 : 1) : 2;
}

/// Groups the outcomes in grouping_pass() order, so that an unconfirmed steady state or a run
/// still converging joins a Newton orbit whatever the order of the starts.
std::vector<int> group_outcomes(const std::vector<StartOutcome>& outcomes,
                                const std::vector<std::vector<double>>& starts,
                                const StateScale& scale, const AttractorOptions& o,
                                std::vector<Attractor>& attractors) {
    std::vector<int> label(outcomes.size(), -1);
    std::vector<std::size_t> representative; // per attractor: its first member
    for (int pass = 0; pass < 3; ++pass) {
        for (std::size_t k = 0; k < outcomes.size(); ++k) {
            const StartOutcome& s = outcomes[k];
            if (s.failed || grouping_pass(s) != pass) continue;
            for (auto& a : attractors)
                if (belongs(s, a, outcomes[representative[static_cast<std::size_t>(a.id)]], scale,
                            o)) {
                    label[k] = a.id;
                    add_member(a, s);
                    break;
                }
            if (label[k] < 0) {
                label[k] = static_cast<int>(attractors.size());
                attractors.push_back(new_attractor(s, starts[k], label[k]));
                representative.push_back(k);
            }
        }
    }
    return label;
}

/// The attractor among `attractors` a run reached (other than `skip`), or -1. A non-periodic
/// attractor's F_m is compared with its largest member's, within that member's spread.
int reached(const StartOutcome& s, const std::vector<Attractor>& attractors,
            const StateScale& scale, const AttractorOptions& o, int skip = -1) {
    if (s.failed) return -1;
    for (const auto& a : attractors) {
        if (a.id == skip) continue;
        StartOutcome representative;
        representative.F_m = a.F_m;
        representative.spread = a.F_m_error;
        if (belongs(s, a, representative, scale, o)) return a.id;
    }
    return -1;
}

/// s continued by `more`, a run from the state where s's runs ended: where it is after both,
/// with its transient's end counted from its first start. Its F_m, run_F_m and spread stay the
/// first run's: what a single run from its start reports, and what a group's F_m is over.
void extend(StartOutcome& s, const StartOutcome& more, int max_steady_period) {
    const long base = s.periods_run;
    s.periodic = more.periodic;
    s.period = more.period;
    s.newton = more.newton;
    s.max_multiplier = more.max_multiplier;
    s.max_multiplier_error = more.max_multiplier_error;
    s.newton_accuracy = more.newton_accuracy;
    // A continuation that never went far from its cycle, after a first run near it for its
    // last max_steady_period periods or more, was near the cycle the first run was approaching:
    // its transient ended where that run's did (last_far + 1), not where the continuation's own
    // test could first see it (max_steady_period + 1 into it). Fig 13's row at f_r = 2.5
    // (|mu| 0.955): 350-period runs read 367, where 500-period runs and gapchain-sim read 70-74
    // (a reviewer's probe, helper-75). Otherwise it may have been far through those untested
    // periods (add_transient() reads -1 so).
    const bool near_at_end = s.last_far < base - max_steady_period;
    const bool near_throughout = more.last_far < 0 && near_at_end;
    if (more.settle_period < 0)
        s.settle_period = -1;
    else if (!near_throughout)
        s.settle_period = base + more.settle_period;
    else
        s.settle_period = s.last_far >= 0 ? s.last_far + 1 : max_steady_period + 1L;
    if (more.last_far >= 0)
        s.last_far = base + more.last_far;
    else if (!near_throughout)
        s.last_far = base + max_steady_period;
    s.periods_run = base + more.periods_run;
    s.state = more.state;
    s.section = more.section;
}

/// The random starts and slice starts labelled `group`, in start order.
std::vector<std::size_t> members_of(const std::vector<int>& labels, int group) {
    std::vector<std::size_t> members;
    for (std::size_t k = 0; k < labels.size(); ++k)
        if (labels[k] == group) members.push_back(k);
    return members;
}

/// How far (scaled, as converging_to()) a state lies from the nearest point of a stable
/// periodic attractor; infinite where there is none.
double distance_to_orbits(const std::vector<double>& state,
                          const std::vector<Attractor>& attractors, const StateScale& scale) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& a : attractors) {
        if (a.period == 0 || a.max_multiplier >= 1.0) continue;
        for (const auto& x : a.section)
            nearest = std::min(nearest, scaled_distance(state, x, scale));
    }
    return nearest;
}

/// A non-periodic group may be a chaotic transient that outlasted its runs (issue 19's Nm = 2
/// row: 1 start in 200 still wandering after 1000 periods, F_m 1.176 against the one
/// attractor's 1.070; Fig 13's row at f_r = 2.05: 44 starts of 100 wandering after 300
/// periods, a saddle whose transients last 5550 periods, all ending on the period-3 orbit). The
/// runs of a few of its members (probe_count()) are continued for `periods` more
/// (confirmation_periods()). A member whose continuation reaches an orbit leaves the group on
/// its own; once one has, the group is a transient, and every other member is continued too
/// (as many as run.max_work affords at that length), so that each start is counted where it
/// went (until 2026-11-28 only the first member was continued, and the group kept all its
/// starts or lost them all: at f_r = 2.05 a chaotic attractor of basin 0.44 was listed).
/// Members that stay keep the group, which left_for_orbits marks as a transient. A
/// continuation that reaches another non-periodic group merges the whole group into it: two
/// windows of one chaotic set that did not overlap at first (member by member, Fig 13's row at
/// f_r = 2.74 with 64 starts swapped members between two such groups and listed one chaos
/// twice). Groups left empty are dropped and ids renumbered in order.
class GroupConfirmation {
public:
    GroupConfirmation(const Dynamics& dyn, const StateScale& scale, const AttractorOptions& o,
                      long periods, const std::vector<std::vector<double>>& starts, int threads,
                      const ProgressCallback& progress, std::vector<StartOutcome>& outcomes,
                      std::vector<Attractor>& attractors, std::vector<int>& labels)
        : m_dyn(dyn), m_scale(scale), m_options(o), m_continued(o), m_starts(starts),
          m_threads(threads), m_progress(progress), m_outcomes(outcomes), m_attractors(attractors),
          m_labels(labels), m_merged_into(attractors.size(), -1),
          m_was_continued(outcomes.size(), false), m_was_tried(outcomes.size(), false),
          m_probed(attractors.size(), false) {
        m_continued.run.periods = periods;
        // A group's continuations together within run.max_work: the search's check counted
        // only its probes (search_work()); a saddle's 44 members at ten run lengths each would
        // exceed it several times.
        const double affordable =
            affordable_simulation_periods(dyn, start_run_options(m_continued.run));
        m_members_affordable =
            static_cast<std::size_t>(std::max(1.0, std::floor(affordable / periods)));
    }

    /// Confirms the group `group` (an index into attractors), and the group it merges into,
    /// if any, in turn; false if progress cancelled.
    bool confirm(int group) {
        for (int g = group;;) {
            if (members_of(m_labels, g).empty()) return true; // merged into an earlier group
            std::optional<int> joined = -1;
            // A group a transient merged into is a transient already: no probe round.
            if (!m_probed[static_cast<std::size_t>(g)] && at(g).left_for_orbits == 0) {
                const std::size_t probes =
                    probe_count(m_options.samples, members_of(m_labels, g).size());
                joined = continue_members(first_of(uncontinued_members(g), probes), g);
                if (!joined) return false;
            }
            m_probed[static_cast<std::size_t>(g)] = true;
            if (*joined < 0 && at(g).left_for_orbits > 0) {
                joined = continue_members(first_of(uncontinued_members(g), affordable_more(g)), g);
                if (!joined) return false;
            }
            if (*joined < 0) return true;
            merge(g, *joined);
            g = *joined;
        }
    }

    /// Rebuilds each chaotic transient (rebuild()) once every group is confirmed, so that it
    /// measures its members against the same orbits as transient_states() later, drops the
    /// groups left empty, renumbers the ids in order, and counts each non-periodic group's
    /// continued starts (members_continued: those still in it, and those that left).
    void renumber() {
        for (std::size_t g = 0; g < m_attractors.size(); ++g)
            if (m_attractors[g].left_for_orbits > 0) rebuild(static_cast<int>(g));
        std::vector<int> new_id(m_attractors.size(), -1);
        std::vector<Attractor> kept;
        for (std::size_t g = 0; g < m_attractors.size(); ++g) {
            const std::vector<std::size_t> members = members_of(m_labels, static_cast<int>(g));
            if (members.empty()) continue;
            Attractor& a = m_attractors[g];
            if (a.period == 0) {
                a.members_continued = a.left_for_orbits;
                for (const std::size_t k : members)
                    if (m_was_continued[k]) ++a.members_continued;
            }
            new_id[g] = static_cast<int>(kept.size());
            kept.push_back(std::move(a));
            kept.back().id = new_id[g];
        }
        for (int& label : m_labels)
            if (label >= 0) label = new_id[static_cast<std::size_t>(label)];
        m_attractors = std::move(kept);
    }

private:
    Attractor& at(int id) { return m_attractors[static_cast<std::size_t>(id)]; }

    int root(int id) const {
        while (m_merged_into[static_cast<std::size_t>(id)] >= 0)
            id = m_merged_into[static_cast<std::size_t>(id)];
        return id;
    }

    /// Continues the runs of `members` by the confirmation's periods from where they ended, in
    /// parallel, and moves each whose continuation reached a periodic attractor, or settled on
    /// an orbit none reached (a new attractor, appended), out of `group`, in member order after
    /// every run (so the moves do not depend on the threads). The non-periodic group the first
    /// of them reached (-1: none); nullopt if progress cancelled.
    std::optional<int> continue_members(const std::vector<std::size_t>& members, int group) {
        if (members.empty()) return -1;
        std::vector<StartOutcome> more(members.size());
        detail::SharedProgress shared(m_progress, static_cast<long>(members.size()));
        const auto end = detail::parallel_for(
            static_cast<long>(members.size()), m_threads,
            [&](long k) {
                more[static_cast<std::size_t>(k)] = run_start(
                    m_dyn, m_continued, m_outcomes[members[static_cast<std::size_t>(k)]].state,
                    shared.item_callback());
            },
            [&](long) { return shared.finished(); });
        if (end == detail::LoopEnd::cancelled) return std::nullopt;
        int joined = -1;
        for (std::size_t m = 0; m < members.size(); ++m) {
            const StartOutcome& next = more[m];
            const std::size_t k = members[m];
            // A continuation that failed (non-finite) would fail again: tried, not continued.
            m_was_tried[k] = true;
            if (next.failed) continue;
            int other = reached(next, m_attractors, m_scale, m_options, group);
            if (other >= 0) other = root(other);
            if (other < 0 && next.periodic) {
                other = static_cast<int>(m_attractors.size());
                m_attractors.push_back(new_attractor(next, m_starts[k], other));
                m_merged_into.push_back(-1);
                m_probed.push_back(true);
            }
            extend(m_outcomes[k], next, m_options.run.max_steady_period);
            m_was_continued[k] = true;
            if (other < 0 || other == group) continue;
            if (at(other).period != 0) {
                m_labels[k] = other;
                ++at(group).left_for_orbits;
            } else if (joined < 0 && !members_of(m_labels, other).empty()) {
                joined = other;
            }
        }
        return joined;
    }

    /// Moves every start of `group` into the non-periodic group `into`, with the count of
    /// those that had left it for orbits: `into` is then a transient too, and its members not
    /// yet continued are continued when confirm() turns to it.
    void merge(int group, int into) {
        for (const std::size_t k : members_of(m_labels, group)) {
            m_labels[k] = into;
            add_member(at(into), m_outcomes[k]);
        }
        at(into).left_for_orbits += at(group).left_for_orbits;
        at(group).left_for_orbits = 0;
        m_merged_into[static_cast<std::size_t>(group)] = into;
    }

    /// The members of `group` whose runs were not continued (or tried) yet, in start order: a
    /// member merged in after its own group's continuation is not run twice, nor one whose
    /// continuation failed.
    std::vector<std::size_t> uncontinued_members(int group) const {
        std::vector<std::size_t> waiting;
        for (const std::size_t k : members_of(m_labels, group))
            if (!m_was_tried[k]) waiting.push_back(k);
        return waiting;
    }

    static std::vector<std::size_t> first_of(const std::vector<std::size_t>& members,
                                             std::size_t count) {
        return {members.begin(),
                members.begin() + static_cast<std::ptrdiff_t>(std::min(count, members.size()))};
    }

    /// How many more members of a transient `group` run.max_work affords to continue: its
    /// continued starts (those that left included, and those whose continuation failed) are
    /// held to it together, but its probes always run.
    std::size_t affordable_more(int group) const {
        const Attractor& a = m_attractors[static_cast<std::size_t>(group)];
        std::size_t continued = static_cast<std::size_t>(a.left_for_orbits);
        for (const std::size_t k : members_of(m_labels, group))
            if (m_was_tried[k]) ++continued;
        return m_members_affordable > continued ? m_members_affordable - continued : 0;
    }

    /// A group some of whose starts left: its first member, state and points become those of
    /// the member that stayed farthest from the stable orbits (the first member's continued
    /// state may be on its way out: at f_r = 2.05, seed 3, its lambda_max run read -1.01, on
    /// the orbit), its F_m the largest of its members' (add_member()).
    void rebuild(int group) {
        const std::vector<std::size_t> kept = members_of(m_labels, group);
        if (kept.empty()) return; // every start left: renumber() drops the group
        std::size_t deepest = kept.front();
        double farthest = -1.0;
        for (const std::size_t k : kept) {
            const double d = distance_to_orbits(m_outcomes[k].state, m_attractors, m_scale);
            if (d > farthest) {
                farthest = d;
                deepest = k;
            }
        }
        Attractor& a = at(group);
        a.initial_state = m_starts[deepest];
        a.state = m_outcomes[deepest].state;
        a.section = m_outcomes[deepest].section;
        a.F_m = m_outcomes[kept.front()].F_m;
        a.F_m_error = m_outcomes[kept.front()].spread;
        for (const std::size_t k : kept)
            add_member(a, m_outcomes[k]);
    }

    const Dynamics& m_dyn;
    const StateScale& m_scale;
    const AttractorOptions& m_options;
    AttractorOptions m_continued; // the search's options, run for the confirmation's periods
    const std::vector<std::vector<double>>& m_starts;
    int m_threads;
    const ProgressCallback& m_progress;
    std::vector<StartOutcome>& m_outcomes;
    std::vector<Attractor>& m_attractors;
    std::vector<int>& m_labels;
    std::vector<int> m_merged_into;    // per group: the group it merged into, -1 if none
    std::vector<bool> m_was_continued; // per start: its continuation ran
    std::vector<bool> m_was_tried;     // per start: its continuation ran or failed
    std::vector<bool> m_probed;        // per group: its probes were continued
    std::size_t m_members_affordable = 1;
};

/// Confirms every non-periodic group of a search (GroupConfirmation); false if progress
/// cancelled.
bool confirm_non_periodic(const Dynamics& dyn, const StateScale& scale, const AttractorOptions& o,
                          long periods, const std::vector<std::vector<double>>& starts, int threads,
                          const ProgressCallback& progress, std::vector<StartOutcome>& outcomes,
                          std::vector<Attractor>& attractors, std::vector<int>& labels) {
    GroupConfirmation confirmation(dyn, scale, o, periods, starts, threads, progress, outcomes,
                                   attractors, labels);
    const std::size_t groups = attractors.size();
    for (std::size_t g = 0; g < groups; ++g)
        if (attractors[g].period == 0 && !confirmation.confirm(static_cast<int>(g))) return false;
    confirmation.renumber();
    return true;
}

/// Whether the runs of a non-periodic group (run.periods, and at least as long again in
/// confirm_non_periodic) last more than four times the contact-free row's decay time to
/// SteadyStateDetector::far_distance of the motion's scale, from the farthest start (reach:
/// in units of that scale, at least 1): the rule by which gapchain-sim tells a chaotic
/// transient from a start-up. Shorter runs have not let the row's damping act: at eps = 1e-9 a
/// 100-period search called the nearly conservative row's wandering a chaotic attractor
/// (lambda_max +0.5, basin 1) though it decays to 1e-3 in 1.4e9 periods; and a box centered
/// 9.4e8 A from rest (40-period runs of a physical scene) called the ring-down a chaotic
/// attractor of F_m 9.4e5 and made it the design value.
bool outlasts_decay(const Dynamics& dyn, const RunOptions& run, double reach) {
    const double tolerance = SteadyStateDetector::far_distance / std::max(1.0, reach);
    return 2 * run.periods > 4 * start_up_decay_periods(dyn, tolerance);
}

/// How far the box's farthest start lies from rest, in units of the motion's scale (A for u,
/// 2 pi f_r A for v).
double box_reach(const AttractorOptions& o, const StateScale& scale) {
    double center = 0.0;
    for (std::size_t i = 0; i < o.center.size(); ++i)
        center = std::max(center, std::abs(o.center[i]) / scale.of(static_cast<int>(i)));
    return center + o.box;
}

/// What a tangent run tells of a group that did not settle on an orbit.
enum class ExponentReading {
    chaos,    ///< lambda_max above the chaos threshold and three errors
    torus,    ///< within three errors of 0, the error a quarter of the threshold at most
    approach, ///< more than three errors below 0: the runs are converging to an orbit
    undecided ///< none of these within 64 lyapunov_periods and run.max_work
};

/// lambda_max, its error and the regime of a group that did not settle on an orbit, from a
/// tangent run on it (from a.state), taken 4, 16 and 64 times longer while undecided.
ExponentReading read_exponent(const Dynamics& dyn, const AttractorOptions& o, Attractor& a) {
    RunOptions run = o.run;
    run.stop_at_steady_state = false;
    // A torus's exponent is 0, an orbit's below, and the error falls as one over the root of
    // the run's length: a reading within the errors of 0 is taken longer until they are small.
    // On Fig 13's row at f_r = 3.2 over 1500 periods the group on its way to the period-15
    // orbit (lambda_max -0.0155) read -0.011 +- 0.075 over 300 periods and -0.014 +- 0.014
    // over 1200; the torus there reads -0.0007 +- 0.015. At f_r = 2.75 the torus read
    // -0.0016 +- 0.036 over 300 periods and was unsettled however long the search ran (a
    // second reader, 2026-11-27). The threshold guards chaos only: a torus's finite-time
    // exponent is not biased upwards below it.
    for (long periods = o.lyapunov_periods;; periods *= 4) {
        run.periods = periods;
        run.transient_periods = periods / 10;
        const LyapunovResult l = chain_lyapunov(dyn, run, 1, a.state);
        a.lambda_max = l.exponents.empty() ? 0.0 : l.exponents.front();
        a.lambda_max_error = l.errors.empty() ? 0.0 : l.errors.front();
        const double sigma3 = 3.0 * a.lambda_max_error;
        const bool chaos = a.lambda_max > std::max(o.chaos_threshold, sigma3);
        a.regime = a.F_m == 0.0 ? Regime::no_contact
                   : chaos      ? Regime::chaotic
                                : Regime::quasi_periodic;
        if (chaos) return ExponentReading::chaos;
        if (a.lambda_max < -sigma3) return ExponentReading::approach;
        if (a.lambda_max <= sigma3 && a.lambda_max_error <= o.chaos_threshold / 4.0)
            return ExponentReading::torus;
        RunOptions longer = run;
        longer.periods = 4 * periods;
        if (a.F_m == 0.0 || longer.periods > 64 * o.lyapunov_periods ||
            run_work(dyn, plan_run(dyn, tangent_run_options(dyn, longer)),
                     static_cast<double>(longer.periods), 1) > o.run.max_work)
            return ExponentReading::undecided;
    }
}

/// States of the starts still in each chaotic transient (a group some of whose starts left
/// for orbits), second and third farthest from the stable orbits (the farthest is its state,
/// GroupConfirmation::rebuild()); empty for other attractors.
std::vector<std::vector<std::vector<double>>>
transient_states(const std::vector<int>& labels, const std::vector<StartOutcome>& outcomes,
                 const std::vector<Attractor>& attractors, const StateScale& scale) {
    std::vector<std::vector<std::vector<double>>> states(attractors.size());
    for (const auto& a : attractors) {
        if (a.left_for_orbits == 0) continue;
        std::vector<std::pair<double, std::size_t>> by_distance;
        for (const std::size_t k : members_of(labels, a.id))
            by_distance.emplace_back(-distance_to_orbits(outcomes[k].state, attractors, scale), k);
        std::stable_sort(by_distance.begin(), by_distance.end(),
                         [](const auto& x, const auto& y) { return x.first < y.first; });
        for (std::size_t i = 1; i < std::min<std::size_t>(3, by_distance.size()); ++i)
            states[static_cast<std::size_t>(a.id)].push_back(outcomes[by_distance[i].second].state);
    }
    return states;
}

/// The exponent of a chaotic transient from its state, and, until one reads chaos, from the
/// others of transient_states(): a run from a saddle leaves it at a random time, and a tangent
/// run that left early reads the orbit's exponent (Fig 13's row at f_r = 2.05, seed 3: -1.01
/// +- 0.005 for a group whose starts wandered for thousands of periods at lambda_max +1.5).
ExponentReading read_transient_exponent(const Dynamics& dyn, const AttractorOptions& o,
                                        const std::vector<std::vector<double>>& others,
                                        Attractor& a) {
    ExponentReading reading = read_exponent(dyn, o, a);
    for (const auto& state : others) {
        if (reading == ExponentReading::chaos) break;
        Attractor trial = a;
        trial.state = state;
        if (read_exponent(dyn, o, trial) != ExponentReading::chaos) continue;
        a = std::move(trial);
        reading = ExponentReading::chaos;
    }
    return reading;
}

/// lambda_max and the regime of each attractor: from the multipliers of a confirmed orbit,
/// else from a tangent run on the attractor (transients: read_transient_exponent() over
/// transient_states); reach is box_reach() (outlasts_decay()).
void characterise(const Dynamics& dyn, const ReducedParameters& p, const AttractorOptions& o,
                  double reach,
                  const std::vector<std::vector<std::vector<double>>>& transient_states,
                  std::vector<Attractor>& attractors, int threads) {
    detail::parallel_for(
        static_cast<long>(attractors.size()), threads,
        [&](long k) {
            Attractor& a = attractors[static_cast<std::size_t>(k)];
            if (a.period != 0 && a.newton_confirmed) {
                a.lambda_max = std::log(a.max_multiplier) * p.f_r / a.period;
                a.lambda_max_error = a.max_multiplier_error / a.max_multiplier * p.f_r / a.period;
                OrbitOptions confirmed;
                confirmed.period = a.period;
                confirmed.max_work = o.run.max_work;
                if (const auto error = orbit_force_error(dyn, confirmed, a.state, a.F_m))
                    a.F_m_error = *error;
                a.regime = a.F_m > 0.0 ? Regime::periodic : Regime::no_contact;
                return;
            }
            // A steady state Newton did not confirm (or could not shoot: exact refuses the
            // row) is periodic still, its exponent unknown: a tangent run on rk4 along such a
            // row's stiff contacts gave +12.4 on a settled orbit (fc = 1e9).
            if (a.period != 0) {
                a.regime = a.F_m > 0.0 ? Regime::periodic : Regime::no_contact;
                a.lambda_max = a.lambda_max_error = std::numeric_limits<double>::quiet_NaN();
                return;
            }
            const ExponentReading reading =
                read_transient_exponent(dyn, o, transient_states[static_cast<std::size_t>(k)], a);
            // A torus has lambda_max = 0 and chaos > 0: a clearly negative one is the approach
            // to a stable orbit that the runs did not reach. A group that never touched is the
            // linear damped row's transient whatever its exponent: that row has one attractor,
            // eq (20)'s orbit (MODEL.md §5), which its runs did not reach (eps = 100 decays at
            // pi / eps = 0.031 per unit time; at f_r = 1e4, 60 periods span 0.006 time units
            // and a 300-period tangent run measured +0.24). Nor is one whose runs the row's
            // damping has not had time to act on (outlasts_decay).
            a.settled = a.F_m > 0.0 && a.left_for_orbits == 0 &&
                        (reading == ExponentReading::chaos || reading == ExponentReading::torus) &&
                        outlasts_decay(dyn, o.run, reach);
        },
        [](long) { return true; });
}

void count_members(const std::vector<int>& labels, long random_starts, AttractorSet& set) {
    for (std::size_t k = 0; k < labels.size(); ++k) {
        const int id = labels[k];
        const bool random = static_cast<long>(k) < random_starts;
        if (id < 0) {
            if (random) ++set.failed;
            continue;
        }
        Attractor& a = set.attractors[static_cast<std::size_t>(id)];
        (random ? a.samples : a.slice_points) += 1;
    }
    const auto n = static_cast<double>(random_starts);
    for (auto& a : set.attractors) {
        a.basin_fraction = static_cast<double>(a.samples) / n;
        // The binomial error vanishes when none or all of the starts reach it, yet N straight
        // outcomes bound the fraction only to about 1/N (one sigma: 1.14 / N).
        a.basin_fraction_error =
            std::max(std::sqrt(a.basin_fraction * (1.0 - a.basin_fraction) / n), 1.0 / n);
        set.unsettled += a.settled ? 0 : 1;
    }
    // The design value is over attractors: an unsettled group's F_m is a transient's, and counts
    // only when nothing settled (then with the warning the tools print).
    const bool any_settled = static_cast<long>(set.attractors.size()) > set.unsettled;
    for (const auto& a : set.attractors)
        if ((a.settled || !any_settled) && (a.F_m > set.F_m_max || set.F_m_max_id < 0)) {
            set.F_m_max = a.F_m;
            set.F_m_max_error = a.F_m_error;
            set.F_m_max_id = a.id;
        }
    set.sample_attractor.assign(labels.begin(), labels.begin() + random_starts);
    set.slice_attractor.assign(labels.begin() + random_starts, labels.end());
}

/// The transient of a start that reached a periodic attractor, as ended (its length) or still
/// going (its length so far). A run that found no steady state may still have ended its
/// transient: near its cycle since last_far + 1 (the cycle entry's definition), approaching it
/// slowly. Near for a few periods, it counts as ended there; else as lasting at least that
/// long (a chaotic transient can pass near a cycle and leave again).
/// Counting every such start as going on to the end of its run made the lifetime long: a
/// transient that ends less than the detection's own delay before the run's end is never
/// seen to settle.
void add_transient(const StartOutcome& s, int max_steady_period, std::vector<long>& ended,
                   std::vector<long>& going) {
    const long run_periods = s.periods_run;
    if (s.settle_period >= 0) {
        ended.push_back(s.settle_period);
        return;
    }
    const long entry = s.last_far >= 0 ? s.last_far + 1 : max_steady_period + 1L;
    // Near for 4 periods: at the Nm = 2 row of docs/attractors.md, 300-period runs (a third of
    // the transients outlast them) gave lifetimes 178 +- 17 (near for 16 periods or more
    // counted as ended), 166 +- 15 (4) and 162 +- 15 (1), against 156 +- 11 from runs that
    // outlast every transient.
    constexpr long near_periods = 4;
    if (run_periods - entry >= near_periods)
        ended.push_back(entry);
    else
        going.push_back(std::min(entry, run_periods));
}

/// Which non-periodic groups' starts search_transients() counts as transients still going.
enum class InTransit {
    every_group, ///< before confirm_non_periodic(): any may be a transient
    left_groups, ///< after: those some of whose starts were seen to leave for orbits
};

/// The transients of the random starts (the first random_starts of labels): those whose label
/// is a periodic attractor, and as still going at the end of their runs, the starts of the
/// non-periodic groups `in_transit` says. Leaving the unconfirmed groups out before the
/// confirmation measured only the transients that ended within the runs: at Fig 13's f_r = 2.05
/// (300-period runs) a lifetime of 2.55 periods, though 44 starts of 100 were on a saddle whose
/// transients last 5550, so that the group was continued one run length and stood.
TransientLifetime search_transients(const std::vector<StartOutcome>& outcomes,
                                    const std::vector<int>& labels, long random_starts,
                                    const std::vector<Attractor>& attractors, int max_steady_period,
                                    InTransit in_transit) {
    std::vector<long> ended, going;
    for (std::size_t k = 0; static_cast<long>(k) < random_starts && k < labels.size(); ++k) {
        if (labels[k] < 0) continue;
        const Attractor& a = attractors[static_cast<std::size_t>(labels[k])];
        if (a.period != 0)
            add_transient(outcomes[k], max_steady_period, ended, going);
        else if (in_transit == InTransit::every_group || a.left_for_orbits > 0)
            going.push_back(outcomes[k].periods_run);
    }
    return transient_lifetime(std::move(ended), std::move(going));
}

/// How long confirm_non_periodic() continues the members of a non-periodic group: ten
/// lifetimes beyond the median of the transients (search_transients(), every non-periodic
/// group's starts counted as still going), where those were measured (a saddle's transient
/// survives that with odds e^-10 / 2); ten times run.periods where periodic attractors were
/// reached but too few transients ended to measure it (Nm = 2 row, 40 starts of 200 periods:
/// 15 still wandered, and continued 200 more, one group stood in one seed of 16; at Fig 13's
/// f_r = 2.05, where a saddle's transients last 5550 periods, the 6 members continued of a
/// group of 44 all stay through 4 x 300 more periods with odds 0.28, through 10 x 300 with
/// odds 0.04); else (no orbit was reached) random_starts / probe_count() / 2 run lengths, the
/// probes of a group of every start together running half the starts' periods (12.5, capped
/// at 10, for 200 starts; 10 for 60; 1.3 for 8), so that a large search may still find a transient
/// that outlasts every start: at Fig 13's f_r = 3.2 with 600-period runs, as long again listed the
/// starts around the period-15 orbit (lifetime about 2100 periods beyond a median of 2300) as a
/// chaotic attractor of basin 0.895. At least run.periods, at most ten times that and what
/// run.max_work allows one run. As long again was too short where the transients are long: at Fig
/// 13's f_r = 3.2, around the period-15 orbit, 4 of 100 starts of 5000 periods still wandered, and
/// the first, continued 5000 more, too; it was listed as a chaotic attractor (F_m 0.262, above the
/// orbit's 0.214, so the design value) though it lands on the orbit at period 10,901. The search
/// measured lifetime 997 periods beyond a median of 2576 there.
long confirmation_periods(const Dynamics& dyn, const RunOptions& run, long random_starts,
                          const TransientLifetime& transients, bool orbit_reached) {
    double periods = static_cast<double>(run.periods);
    if (std::isfinite(transients.lifetime) && std::isfinite(transients.from_period))
        periods = std::max(periods, transients.from_period + 10.0 * transients.lifetime);
    else if (orbit_reached)
        periods = 10.0 * static_cast<double>(run.periods);
    else
        periods *= std::max(1.0, 0.5 * static_cast<double>(random_starts) /
                                     static_cast<double>(probe_count(
                                         random_starts, static_cast<std::size_t>(random_starts))));
    // The continuations run as the starts do, their comparison runs included: priced without
    // them, 2000-period continuations of the Nm = 2 row were refused after every start had run.
    const double affordable = affordable_simulation_periods(dyn, start_run_options(run));
    // Whole periods within the budget (rounding up made the run refused after every start had
    // run), and within validate(RunOptions)'s 1e9.
    periods = std::min(
        {std::ceil(periods), 10.0 * static_cast<double>(run.periods), std::floor(affordable), 1e9});
    return std::max(run.periods, static_cast<long>(periods));
}

/// The settling statistics and F_m_runs of each attractor over its random starts (an attractor
/// only slice starts reach keeps NaN: it has none). A start that joined a periodic attractor
/// without settling (still converging, or a transient group merged into it) is still settling:
/// its lifetime is longer than its run.
void settle_statistics(const std::vector<StartOutcome>& outcomes, int max_steady_period,
                       AttractorSet& set) {
    std::vector<std::vector<long>> lifetimes(set.attractors.size());
    constexpr long censored = std::numeric_limits<long>::max();
    for (std::size_t k = 0; k < set.sample_attractor.size(); ++k) {
        const StartOutcome& s = outcomes[k];
        set.sample_settle_period.push_back(s.failed ? -1 : s.settle_period);
        set.sample_F_m.push_back(s.failed ? 0.0 : s.run_F_m);
        const int id = set.sample_attractor[k];
        if (id < 0) continue;
        Attractor& a = set.attractors[static_cast<std::size_t>(id)];
        if (std::isnan(a.F_m_runs) || s.run_F_m > a.F_m_runs) {
            a.F_m_runs = s.run_F_m;
            a.F_m_runs_error = s.spread;
        }
        if (a.period == 0) continue;
        lifetimes[static_cast<std::size_t>(id)].push_back(s.settle_period >= 0 ? s.settle_period
                                                                               : censored);
    }
    set.transients = search_transients(outcomes, set.sample_attractor,
                                       static_cast<long>(set.sample_attractor.size()),
                                       set.attractors, max_steady_period, InTransit::left_groups);
    for (auto& a : set.attractors) {
        auto& t = lifetimes[static_cast<std::size_t>(a.id)];
        if (t.empty()) continue;
        std::sort(t.begin(), t.end());
        const std::size_t mid = t.size() / 2;
        // The usual median (the mean of the middle two of an even count); unknown if either
        // is a start still settling.
        const long upper = t[mid], lower = t.size() % 2 == 1 ? upper : t[mid - 1];
        if (upper != censored) a.settle_median = 0.5 * (static_cast<double>(lower) + upper);
        a.still_settling = std::count(t.begin(), t.end(), censored);
        if (t.front() != censored)
            a.settle_max =
                static_cast<double>(*std::prev(std::lower_bound(t.begin(), t.end(), censored)));
    }
}

std::vector<double> axis_values(const AttractorOptions& o, const StateScale& scale, int index) {
    const int r = o.slice->resolution;
    const double half = o.box * scale.of(index);
    const double middle = o.center.empty() ? 0.0 : o.center[static_cast<std::size_t>(index)];
    std::vector<double> v(static_cast<std::size_t>(r));
    for (int i = 0; i < r; ++i)
        v[static_cast<std::size_t>(i)] = middle - half + 2.0 * half * i / (r - 1);
    return v;
}

} // namespace

std::vector<std::vector<double>> attractor_starts(const ReducedParameters& p,
                                                  const AttractorOptions& o) {
    validate(p, o);
    const StateScale scale = state_scale(p);
    const int dim = 2 * p.Nm;
    const std::vector<double> center = box_center(o, p.Nm);
    std::vector<std::vector<double>> starts;
    for (long k = 0; k < o.samples; ++k) {
        std::vector<double> x = center;
        for (int i = 0; i < dim; ++i) {
            const double u = detail::unit_interval(detail::hash3(o.seed, k, i));
            x[static_cast<std::size_t>(i)] += o.box * scale.of(i) * (2.0 * u - 1.0);
        }
        starts.push_back(std::move(x));
    }
    if (!o.slice) return starts;
    const auto xs = axis_values(o, scale, o.slice->first);
    const auto ys = axis_values(o, scale, o.slice->second);
    for (double y : ys)
        for (double x : xs) {
            std::vector<double> s = center;
            s[static_cast<std::size_t>(o.slice->first)] = x;
            s[static_cast<std::size_t>(o.slice->second)] = y;
            starts.push_back(std::move(s));
        }
    return starts;
}

AttractorSet find_attractors(const ReducedParameters& p, const AttractorOptions& o,
                             const ProgressCallback& progress) {
    const auto clock = std::chrono::steady_clock::now();
    const std::vector<std::vector<double>> starts = attractor_starts(p, o);
    const Dynamics dyn = Dynamics::paper_row(p);
    const StateScale scale = state_scale(p);
    AttractorSet set;
    set.amplitude = scale.u;
    set.threads_used = detail::thread_count(o.threads);
    std::vector<StartOutcome> outcomes(starts.size());
    detail::SharedProgress shared(progress, static_cast<long>(starts.size()));
    const auto end = detail::parallel_for(
        static_cast<long>(starts.size()), set.threads_used,
        [&](long k) { outcomes[k] = run_start(dyn, o, starts[k], shared.item_callback()); },
        [&](long) { return shared.finished(); });
    if (end == detail::LoopEnd::cancelled) {
        set.cancelled = true;
        return set;
    }
    auto labels = group_outcomes(outcomes, starts, scale, o, set.attractors);
    // The extra runs come after every start: they report the search as done, and may cancel it.
    const ProgressCallback at_end = [&](double) { return !progress || progress(1.0); };
    const bool orbit_reached = std::any_of(set.attractors.begin(), set.attractors.end(),
                                           [](const Attractor& a) { return a.period != 0; });
    const long continued =
        confirmation_periods(dyn, o.run, o.samples,
                             search_transients(outcomes, labels, o.samples, set.attractors,
                                               o.run.max_steady_period, InTransit::every_group),
                             orbit_reached);
    if (std::any_of(set.attractors.begin(), set.attractors.end(),
                    [](const Attractor& a) { return a.period == 0; }))
        set.confirmation_periods = continued;
    if (!confirm_non_periodic(dyn, scale, o, continued, starts, set.threads_used, at_end, outcomes,
                              set.attractors, labels)) {
        set.attractors.clear();
        set.cancelled = true;
        return set;
    }
    characterise(dyn, p, o, box_reach(o, scale),
                 transient_states(labels, outcomes, set.attractors, scale), set.attractors,
                 set.threads_used);
    count_members(labels, o.samples, set);
    settle_statistics(outcomes, o.run.max_steady_period, set);
    if (o.slice) {
        set.slice_first = axis_values(o, scale, o.slice->first);
        set.slice_second = axis_values(o, scale, o.slice->second);
    }
    set.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
    return set;
}

double detail::search_body_steps(const Dynamics& dyn, const AttractorOptions& options) {
    return search_work(dyn, plan_run(dyn, options.run), options).body_steps;
}

int detail::attractor_reached_from(const Dynamics& dyn, const AttractorOptions& options,
                                   const std::vector<double>& state,
                                   const std::vector<Attractor>& attractors,
                                   const StateScale& scale, const ProgressCallback& keep_going) {
    return reached(run_start(dyn, options, state, keep_going), attractors, scale, options);
}

} // namespace gapchain
