#include "gapchain/observers.hpp"
#include "gapchain/run.hpp"

#include "detail/hermite.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

using namespace gapchain;

namespace {
// Largest force over all contacts of a tracker.
double largest_force(const MaxForceTracker& tracker) {
    double f = 0.0;
    for (const ContactMaximum& c : tracker.contacts())
        f = std::max(f, c.force);
    return f;
}
} // namespace

TEST_CASE("MaxForceTracker: the half-window maxima equal the maxima of runs recording only that "
          "half") {
    // A row whose largest force comes in the first half (the start-up transient): the second
    // half's peaks stay below the contacts' records, the case where a half maximum could be
    // missed (before the fix, by 3.9e-3 here).
    const ReducedParameters p{5, 60, 0.3, 0.3, 1.3};
    const Dynamics dyn = Dynamics::paper_row(p);
    // Steps that do not end on contact switches put whole contacts inside steps, where the
    // tracker decides from a bound whether a peak is worth locating.
    StepPlan plan = plan_step(dyn, Scheme::rk4, 1e-4);
    plan.split_at_switches = false;
    constexpr long periods = 200, split = 100;

    // One run records everything and splits; two more record only one half each (the first
    // stops at the split, the second discards it as a transient) on the same step grid.
    auto run_with = [&](long total, long transient, long split_period) {
        auto stepper = make_stepper(plan, dyn);
        MaxForceTracker tracker(dyn, split_period);
        std::array<Observer*, 1> observers{&tracker};
        std::vector<double> y(2 * p.Nm, 0.0);
        const RunOutcome out = run(dyn, *stepper, plan, {total, transient, 0.0}, y, observers);
        REQUIRE(out.status == RunStatus::completed);
        return tracker;
    };
    const MaxForceTracker whole = run_with(periods, 0, split);
    const MaxForceTracker first = run_with(split, 0, -1);
    const MaxForceTracker second = run_with(periods, split, -1);

    MESSAGE("halves " << whole.first_half_max() << ", " << whole.second_half_max());
    CHECK(whole.first_half_max() == doctest::Approx(largest_force(first)).epsilon(1e-12));
    CHECK(whole.second_half_max() == doctest::Approx(largest_force(second)).epsilon(1e-12));
    CHECK(std::max(whole.first_half_max(), whole.second_half_max()) ==
          doctest::Approx(largest_force(whole)).epsilon(1e-12));
    // Not trivially equal: the record is in the first half, well above the second's maximum.
    CHECK(whole.first_half_max() > 1.05 * whole.second_half_max());
}

TEST_CASE("MaxForceTracker: the tail spread is read from the maxima of runs recording one "
          "period each") {
    // The tracker keeps the largest per-period maxima without locating every peak (a peak
    // below the smallest kept one is skipped): the tail must be the one of every period's
    // maximum, each from a tracker of its own on the same trajectory.
    const ReducedParameters p{5, 60, 0.5, 0.06, 3.3}; // Fig 13's line, not settling
    const Dynamics dyn = Dynamics::paper_row(p);
    const StepPlan plan = plan_step(dyn, Scheme::rk4, 1e-4);
    constexpr long periods = 80;
    auto stepper = make_stepper(plan, dyn);
    MaxForceTracker whole(dyn);
    std::array<Observer*, 1> all{&whole};
    std::vector<double> y(2 * p.Nm, 0.0);
    REQUIRE(run(dyn, *stepper, plan, {periods, 0, 0.0}, y, all).status == RunStatus::completed);

    std::vector<double> maxima;
    auto one_at_a_time = make_stepper(plan, dyn);
    std::vector<double> z(2 * p.Nm, 0.0);
    for (long n = 0; n < periods; ++n) {
        MaxForceTracker period(dyn);
        std::array<Observer*, 1> one{&period};
        const RunSpan span{n + 1, 0, static_cast<double>(n) * dyn.period(), n};
        REQUIRE(run(dyn, *one_at_a_time, plan, span, z, one).status == RunStatus::completed);
        maxima.push_back(largest_force(period));
    }
    double apart = 0.0;
    for (int i = 0; i < 2 * p.Nm; ++i)
        apart = std::max(apart, std::abs(y[i] - z[i]));
    // The same trajectory: 80 periods of this chaotic row part runs restarted at each period by
    // 3e-8 (120 periods by 3e-5, which moves the tail).
    REQUIRE(apart < 1e-6);
    // pi / sqrt(6) times the mean excess of the r - 1 largest of the first `recorded` maxima
    // over the r-th.
    const auto tail_of = [&](long recorded, int r) {
        std::vector<double> first(maxima.begin(), maxima.begin() + recorded);
        std::sort(first.begin(), first.end(), std::greater<>());
        double excess = 0.0;
        for (int i = 0; i + 1 < r; ++i)
            excess += first[static_cast<std::size_t>(i)] - first[static_cast<std::size_t>(r - 1)];
        return std::numbers::pi / std::sqrt(6.0) * excess / (r - 1);
    };
    const double expected = tail_of(periods, MaxForceTracker::tail_periods);
    MESSAGE("tail spread " << whole.tail_spread() << ", F_m " << largest_force(whole));
    CHECK(expected > 1e-3 * largest_force(whole)); // a spread to read
    CHECK(whole.tail_spread() == doctest::Approx(expected).epsilon(1e-9));
    CHECK(largest_force(whole) ==
          doctest::Approx(*std::max_element(maxima.begin(), maxima.end())).epsilon(1e-12));
    // A shorter record reads its top quarter (a 40-period one, its top 10; records under 80
    // periods had none, and one draw from the halves as their bar); fewer than 4
    // min_tail_periods recorded periods have no tail to read.
    for (const long recorded : {40L, 4L * MaxForceTracker::min_tail_periods - 1}) {
        CAPTURE(recorded);
        MaxForceTracker short_run(dyn);
        std::array<Observer*, 1> brief{&short_run};
        std::vector<double> x(2 * p.Nm, 0.0);
        auto again = make_stepper(plan, dyn);
        REQUIRE(run(dyn, *again, plan, {recorded, 0, 0.0}, x, brief).status ==
                RunStatus::completed);
        const int r = static_cast<int>(recorded / 4);
        if (r < MaxForceTracker::min_tail_periods)
            CHECK(short_run.tail_spread() == 0.0);
        else
            CHECK(short_run.tail_spread() == doctest::Approx(tail_of(recorded, r)).epsilon(1e-9));
    }
}

namespace {
// Closings and the largest force at the step ends, per contact: what any scan of the run must
// at least find, counted without the tracker's bounds and records. A contact's side after a
// step end is the sign of its gap, or, on the surface to round-off (a step split at a switch),
// the sign of its rate: a split step that ends where the contact opens and the next that ends
// where it closes again both end on the surface, where the sign of the gap says nothing.
class StepEndForces final : public Observer {
public:
    explicit StepEndForces(const Dynamics& dyn)
        : m_dyn(dyn), closings(dyn.gaps(), 0), largest(dyn.gaps(), 0.0), m_closed(dyn.gaps()) {}
    void on_step(const StepView& step) override {
        const int n = m_dyn.bodies();
        if (!m_started)
            for (int j = 0; j < m_dyn.gaps(); ++j)
                m_closed[j] = closed_after(j, step.y0);
        m_started = true;
        for (int j = 0; j < m_dyn.gaps(); ++j) {
            const bool closed = closed_after(j, step.y1);
            if (step.recording && closed && !m_closed[j]) ++closings[j];
            m_closed[j] = closed;
        }
        if (!step.recording) return;
        for (int j = 0; j < m_dyn.gaps(); ++j) {
            const double g1 = m_dyn.gap(j, step.y1);
            const double rate = m_dyn.gap_rate(j, step.y1 + n);
            const double force = m_dyn.force_at_penetration(j, g1, rate);
            largest[j] = std::max(largest[j], force);
            double& half = half_largest[step.period < split_period ? 0 : 1];
            half = std::max(half, force);
        }
    }
    const Dynamics& m_dyn;
    std::vector<long> closings;
    std::vector<double> largest;
    long split_period = 20;
    double half_largest[2] = {0.0, 0.0};

private:
    bool closed_after(int j, const double* y) const {
        const double g = m_dyn.gap(j, y);
        if (std::abs(g) > 1e-12) return g > 0.0;
        return m_dyn.gap_rate(j, y + m_dyn.bodies()) > 0.0;
    }
    std::vector<char> m_closed;
    bool m_started = false;
};
} // namespace

TEST_CASE("MaxForceTracker: every contact's closings and step-end forces are counted, whatever "
          "its record (a stiff row with many contacts closed)") {
    // The tracker scans only the contacts whose penetration could beat their records; a
    // contact skipped wrongly would lose a closing or a larger force. Nm = 20, fc = 2000,
    // e_r = 0.02: most contacts close every few steps.
    const ReducedParameters p{20, 2000, 0.2, 0.02, 1.0};
    for (const char* law : {"linear", "hertz", "hunt_crossley"}) {
        const std::string law_name = law;
        CAPTURE(law_name);
        Chain chain = Dynamics::paper_row(p).chain();
        chain.law = std::string(law) == "linear"  ? ContactLaw::linear
                    : std::string(law) == "hertz" ? ContactLaw::hertz
                                                  : ContactLaw::hunt_crossley;
        chain.contact_damping = chain.law == ContactLaw::hunt_crossley ? 2.0 : 0.0;
        const Dynamics dyn(chain, Dynamics::paper_row(p).ground_motion());
        for (bool split : {true, false}) {
            CAPTURE(split);
            StepPlan plan = plan_step(dyn, Scheme::rk4, 1e-4);
            plan.split_at_switches = split;
            auto stepper = make_stepper(plan, dyn);
            MaxForceTracker tracker(dyn, 20);
            StepEndForces ends(dyn);
            std::array<Observer*, 2> observers{&tracker, &ends};
            std::vector<double> y(2 * p.Nm, 0.0);
            REQUIRE(run(dyn, *stepper, plan, {30, 10, 0.0}, y, observers).status ==
                    RunStatus::completed);
            long closings = 0;
            for (int j = 0; j < dyn.gaps(); ++j) {
                const ContactMaximum& c = tracker.contacts()[j];
                closings += ends.closings[j];
                // Split steps end on every switch, so closings are all at step ends; whole
                // steps may also hold a brief contact that opens again inside the step.
                if (split)
                    CHECK(c.impacts == ends.closings[j]);
                else
                    CHECK(c.impacts >= ends.closings[j]);
                CHECK(c.force >= ends.largest[j]);
                // An elastic force peak inside a step of h omega <= 0.4 lies within 5 % of the
                // step ends' (Hunt-Crossley's damping term peaks sharper, while closing).
                if (!dyn.dissipative_contacts()) CHECK(c.force <= 1.05 * ends.largest[j] + 1e-12);
            }
            CHECK(closings > 500); // the case this test is for: contacts close all the time
            // Each window half has its own records (the second starts again from 0, below the
            // contacts' own records): a contact skipped for its record would lose them.
            CHECK(tracker.first_half_max() >= ends.half_largest[0]);
            CHECK(tracker.second_half_max() >= ends.half_largest[1]);
            if (!dyn.dissipative_contacts()) {
                CHECK(tracker.first_half_max() <= 1.05 * ends.half_largest[0] + 1e-12);
                CHECK(tracker.second_half_max() <= 1.05 * ends.half_largest[1] + 1e-12);
            }
        }
    }
}

TEST_CASE("MaxForceTracker: a contact that opens between two switches and closes again is one "
          "impact, whichever side of the surface round-off puts the switches on") {
    // Nm = 1, the left wall: steps end where the contact opens (gap s1) and where it closes
    // again (gap s2), both 0 but for round-off, as a run split at switches gives them (a few
    // ulps of the clearance, 0.5: 1e-17 would round to 0 in u + e). The
    // contact starts closed (no impact counted for the start), so each run has one impact: the
    // reclosing. With both switches on the closed side, no step started open, and it was lost.
    const Dynamics dyn = Dynamics::paper_row({1, 100, 0.5, 0.5, 1.0});
    const double e = dyn.chain().clearance[0];
    // The state whose left-wall gap -u - e is g, closing at the rate -v.
    auto at = [&](double g, double rate) { return std::array<double, 2>{-(g + e), -rate}; };
    for (const double s1 : {1e-15, -1e-15})
        for (const double s2 : {1e-15, -1e-15}) {
            CAPTURE(s1);
            CAPTURE(s2);
            const std::array<std::array<double, 2>, 4> y{at(2e-3, -1.0), at(s1, -0.5), at(s2, 0.5),
                                                         at(2e-3, 1.0)};
            MaxForceTracker tracker(dyn);
            for (int k = 0; k < 3; ++k)
                tracker.on_step({0.01 * k, 0.01 * (k + 1), y[k].data(), y[k + 1].data(), 0, true});
            CHECK(tracker.contacts()[0].impacts == 1);
            CHECK(tracker.contacts()[1].impacts == 0);
        }
    // A dip that stays closed (the gap falls to 1e-3 and rises again) is no impact.
    MaxForceTracker closed(dyn);
    const auto a = at(2e-3, -0.05), b = at(2e-3, 0.05);
    closed.on_step({0.0, 0.01, a.data(), b.data(), 0, true});
    CHECK(closed.contacts()[0].impacts == 0);
}

TEST_CASE("SteadyStateDetector: a cycle approached along a negative multiplier is reported with "
          "its minimal period") {
    // y_n = c_(n mod 3) + (-0.85)^n: a period-3 cycle, deviation multiplied by -0.614 every three
    // periods. The 6-period distance is 1.6x smaller than the 3-period one, so the 6 test passes
    // first; the detector must still say 3.
    const std::array<double, 3> cycle{0.2, -0.5, 0.9};
    constexpr double tolerance = 1e-8;
    SteadyStateDetector steady(1, 8, tolerance, 0);
    long stopped_at = -1;
    double deviation = 1.0;
    for (long n = 0; n < 400 && stopped_at < 0; ++n, deviation *= -0.85) {
        const double y = cycle[n % 3] + deviation;
        if (steady.on_period(n, static_cast<double>(n), &y)) stopped_at = n;
    }
    REQUIRE(stopped_at > 0);
    CHECK(steady.period() == 3);
    // Slower approaches (0.86 and 0.95 per three periods), and one found long before the
    // earliest stop, are still reported as period 3.
    for (const auto& [per_period, earliest] :
         {std::pair{-0.95, 0L}, std::pair{-0.983, 0L}, std::pair{-0.9, 600L}}) {
        SteadyStateDetector slow(1, 8, tolerance, earliest);
        stopped_at = -1;
        deviation = 1.0;
        for (long n = 0; n < 4000 && stopped_at < 0; ++n, deviation *= per_period) {
            const double y = cycle[n % 3] + deviation;
            if (slow.on_period(n, static_cast<double>(n), &y)) stopped_at = n;
        }
        CAPTURE(per_period);
        REQUIRE(stopped_at > 0);
        CHECK(slow.period() == 3);
    }
    // A cycle of genuine period 6 (two period-3 halves 10x the tolerance apart) stays 6.
    SteadyStateDetector doubled(1, 8, tolerance, 0);
    stopped_at = -1;
    deviation = 1.0;
    for (long n = 0; n < 400 && stopped_at < 0; ++n, deviation *= -0.85) {
        const double split = (n / 3) % 2 == 0 ? 5.0 * tolerance : -5.0 * tolerance;
        const double y = cycle[n % 3] + split + deviation;
        if (doubled.on_period(n, static_cast<double>(n), &y)) stopped_at = n;
    }
    REQUIRE(stopped_at > 0);
    CHECK(doubled.period() == 6);
}

TEST_CASE("SteadyStateDetector: a cycle longer than max_period is named by longer_cycle()") {
    // y_n = c_(n mod k) + 0.5^n with distinct c: a k-cycle approached quickly. With max_period 8
    // a 7-cycle is a steady state; an 11-cycle and a 30-cycle are not, and longer_cycle() names
    // them (up to 4 x 8 = 32); a 40-cycle is beyond, and a sequence that never repeats has none.
    const auto feed = [](SteadyStateDetector& steady, long k, long periods) {
        double deviation = 1.0;
        for (long n = 0; n < periods; ++n, deviation *= 0.5) {
            const double y = 1.0 + 0.1 * static_cast<double>(n % k) + deviation;
            if (steady.on_period(n, static_cast<double>(n), &y)) break;
        }
    };
    for (const auto& [k, steady_period, longer] :
         {std::tuple{7L, std::optional<int>(7), std::optional<int>()},
          std::tuple{11L, std::optional<int>(), std::optional<int>(11)},
          std::tuple{30L, std::optional<int>(), std::optional<int>(30)},
          std::tuple{40L, std::optional<int>(), std::optional<int>()}}) {
        SteadyStateDetector steady(1, 8, 1e-10, 0);
        feed(steady, k, 300);
        CAPTURE(k);
        CHECK(steady.period() == steady_period);
        CHECK(steady.longer_cycle() == longer);
    }
    // Too few boundaries for the test at that lag (it compares two pairs k apart): nothing.
    SteadyStateDetector early(1, 8, 1e-10, 0);
    feed(early, 30, 31);
    CHECK_FALSE(early.longer_cycle().has_value());
    // A logistic-map sequence (chaotic) repeats with no lag.
    SteadyStateDetector chaotic(1, 8, 1e-10, 0);
    double x = 0.3;
    for (long n = 0; n < 300; ++n, x = 3.99 * x * (1.0 - x))
        chaotic.on_period(n, static_cast<double>(n), &x);
    CHECK_FALSE(chaotic.period().has_value());
    CHECK_FALSE(chaotic.longer_cycle().has_value());
    // A torus whose rotation is near 1 / 47 comes back within 3e-4 after 47 periods, forever:
    // no cycle (a reviewer's probe found one at Fig 13's f_r = 3.2, named 47 by a 1e-3 test).
    SteadyStateDetector torus(1, 16, 1e-10, 0);
    for (long n = 0; n < 1000; ++n) {
        const double y = std::cos(2.0 * std::numbers::pi * (1.0 / 47.0 + 1e-6) * n);
        torus.on_period(n, static_cast<double>(n), &y);
    }
    CHECK_FALSE(torus.period().has_value());
    CHECK_FALSE(torus.longer_cycle().has_value());
}

TEST_CASE(
    "SteadyStateDetector: a period-1 cycle approached along a turning deviation is period 1") {
    // A lightly damped body (eps = 0.01) forced at f_r = 1.3: its free deviation decays by
    // exp(-2 pi eps / f_r) and turns by 2 pi sqrt(1 - eps^2) / f_r per forcing period, u and
    // v = u' on scales 1 and 2 pi. Four periods make 3.08 turns, so the 4-period test passes
    // before the 1-period one; the stored cycle is (0.3, -2.1).
    // At f_r = 2.7, 8 periods make 2.96 turns and 2 make 0.74: 8 is shortened to 2, then 1.
    // Near f_r = 2 j / m the largest component, sampled once a period, beats over tens of
    // periods (1.944, 3.9: a second read found period 2 and 4 there).
    const double pi = 3.14159265358979323846;
    for (const auto& [eps, f_r, phase] :
         {std::tuple{0.01, 1.3, 0.0}, std::tuple{0.01, 1.3, 0.7}, std::tuple{0.01, 1.3, 1.9},
          std::tuple{0.01, 2.7, 0.0}, std::tuple{0.01, 2.7, 1.1}, std::tuple{0.01, 1.9444, 0.0},
          std::tuple{0.01, 3.9, 0.0}, std::tuple{0.003, 2.0, 0.4}, std::tuple{0.003, 3.8, 2.0},
          std::tuple{0.003, 0.66, 0.0}}) {
        const double decay = std::exp(-2 * pi * eps / f_r);
        const double turn = 2 * pi * std::sqrt(1 - eps * eps) / f_r;
        SteadyStateDetector steady(2, 16, 1e-10, 0, 2 * pi);
        long stopped_at = -1;
        double size = 0.5;
        for (long n = 0; n < 5000 && stopped_at < 0; ++n, size *= decay) {
            const double angle = phase + turn * static_cast<double>(n);
            const std::array<double, 2> y{0.3 + size * std::cos(angle),
                                          -2.1 - 2 * pi * size * std::sin(angle)};
            if (steady.on_period(n, static_cast<double>(n), y.data())) stopped_at = n;
        }
        CAPTURE(eps);
        CAPTURE(f_r);
        CAPTURE(phase);
        REQUIRE(stopped_at > 0);
        CHECK(steady.period() == 1);
    }
}

TEST_CASE("SteadyStateDetector: a genuine period-2 orbit approached along a turning deviation "
          "stays 2") {
    // The two points of the orbit differ by 10 tolerances in u; the deviation turns as in the
    // test above (eps = 0.01, f_r = 5.0109: 10 periods nearly close its turns, so 10 passes
    // first, with divisor distances 1 and 5 stuck at the split while 2's decays).
    const double eps = 0.01, f_r = 5.0109, pi = 3.14159265358979323846, tolerance = 1e-10;
    const double decay = std::exp(-2 * pi * eps / f_r);
    const double turn = 2 * pi * std::sqrt(1 - eps * eps) / f_r;
    for (const double phase : {0.0, 1.75, 3.0}) {
        SteadyStateDetector steady(2, 16, tolerance, 0, 2 * pi);
        long stopped_at = -1;
        double size = 0.5;
        for (long n = 0; n < 20000 && stopped_at < 0; ++n, size *= decay) {
            const double angle = phase + turn * static_cast<double>(n);
            const double split = n % 2 == 0 ? 5 * tolerance : -5 * tolerance;
            const std::array<double, 2> y{0.3 + split + size * std::cos(angle),
                                          -2.1 - 2 * pi * size * std::sin(angle)};
            if (steady.on_period(n, static_cast<double>(n), y.data())) stopped_at = n;
        }
        CAPTURE(phase);
        REQUIRE(stopped_at > 0);
        CHECK(steady.period() == 2);
    }
}

TEST_CASE("the quintic Hermite interpolant's crossings are the roots of the quintic it "
          "reproduces, and an exact zero is returned as it is") {
    // A quintic with roots at 0.3, 1.1 and 1.7 (and two outside [0, h]), h = 2: the interpolant
    // from its values and first two derivatives at both ends is the quintic itself.
    const double h = 2.0;
    const std::array<double, 5> roots{0.3, 1.1, 1.7, -1.0, 3.0};
    auto p = [&](double t, int derivative) {
        // Value, first or second derivative by the product rule over the five factors (each
        // unordered pair of differentiated factors appears twice in the second derivative).
        double sum = 0.0;
        for (int mask = 0; mask < 32; ++mask) {
            if (__builtin_popcount(static_cast<unsigned>(mask)) != derivative) continue;
            double term = derivative == 2 ? 2.0 : 1.0;
            for (int k = 0; k < 5; ++k)
                term *= (mask >> k & 1) ? 1.0 : t - roots[k];
            sum += term;
        }
        return sum;
    };
    const detail::QuinticHermite q(p(0, 0), p(0, 1), p(0, 2), p(h, 0), p(h, 1), p(h, 2), h);
    CHECK(q.crossing(0.0, 0.0, 0.7) == doctest::Approx(0.3).epsilon(1e-14));
    CHECK(q.crossing(0.0, 0.7, 1.4) == doctest::Approx(1.1).epsilon(1e-14));
    CHECK(q.crossing(0.0, 1.4, 2.0) == doctest::Approx(1.7).epsilon(1e-14));
    // The bracket's midpoint is an exact root of a line: the search starts there and returns
    // it, where bisecting on would move it by ~1e-15 h.
    const detail::QuinticHermite line(-1.0, 1.0, 0.0, 1.0, 1.0, 0.0, h);
    CHECK(line.crossing(0.0, 0.0, h) == 1.0);
    CHECK(line.crossing(0.25, 0.0, h) == doctest::Approx(1.25).epsilon(1e-15));
    // (t - 1)^2 (t - 1.5) touches 0 at the midpoint without crossing: the crossing is 1.5.
    const detail::QuinticHermite touch(-1.5, 4.0, -7.0, 0.5, 2.0, 5.0, h);
    CHECK(touch.crossing(0.0, 0.0, h) == doctest::Approx(1.5).epsilon(1e-14));
}
