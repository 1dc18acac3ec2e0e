#include "gapchain/continuation.hpp"
#include "gapchain/orbit.hpp"

#include "detail/traced_orbits.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

using namespace gapchain;
using std::numbers::pi;

TEST_CASE("a contact-free branch: no special point, MODEL.md's multipliers all along") {
    const double eps = 0.2;
    const ReducedParameters p{2, 50, eps, 1e3, 0.5};
    ContinuationOptions o;
    o.from = 0.5;
    o.to = 1.5;
    o.step = 0.05;
    o.max_step = 0.1;
    o.transient_periods = 0;
    const ContinuationResult r = continue_orbits(p, o);
    REQUIRE(r.points.size() > 5);
    CHECK(r.special.empty());
    CHECK(r.branch_end.front() == "reached the end value f_r = 1.5");
    // The last point is on the end value, not a step past it.
    CHECK(r.points.back().value == 1.5);
    for (const auto& point : r.points) {
        CHECK(point.stable);
        CHECK(point.F_m == 0.0);
        CHECK(point.max_multiplier ==
              doctest::Approx(std::exp(-2 * pi * eps / point.value)).epsilon(1e-8));
    }
}

TEST_CASE("an undamped contact-free branch is neutral all along, not stable") {
    // eps = 0: det M = 1, every multiplier on the unit circle; a largest one computed a hair
    // below 1 was reported stable.
    const ReducedParameters p{2, 100, 0.0, 5.0, 0.5};
    ContinuationOptions o;
    o.from = 0.5;
    o.to = 0.55;
    o.transient_periods = 0;
    const ContinuationResult r = continue_orbits(p, o);
    REQUIRE(r.points.size() > 2);
    for (const auto& point : r.points) {
        CHECK_FALSE(point.stable);
        CHECK(point.max_multiplier == doctest::Approx(1.0).epsilon(1e-9));
    }
}

TEST_CASE("a cancel inside a shooting ends the continuation as cancelled") {
    const ReducedParameters p{5, 60, 0.5, 0.06, 2.6};
    ContinuationOptions o;
    o.from = 2.6;
    o.to = 2.7;
    o.transient_periods = 200;
    long calls = 0;
    // Stopped after the transient run and the first Newton search, inside the branch's walk.
    long stop_at = 0;
    std::size_t whole_points = 0;
    {
        const ContinuationResult whole = continue_orbits(p, o, {}, [&](double) {
            ++stop_at;
            return true;
        });
        REQUIRE_FALSE(whole.cancelled);
        REQUIRE(stop_at > 20);
        whole_points = whole.points.size();
    }
    const ContinuationResult r =
        continue_orbits(p, o, {}, [&](double) { return ++calls < stop_at / 2; });
    CHECK(r.cancelled);
    // After the refusal each shooting still asks once, at its first check, and fails at once.
    CHECK(calls < stop_at);
    CHECK(r.points.size() < whole_points);
    REQUIRE_FALSE(r.branch_end.empty());
    CHECK(r.branch_end.back() == "cancelled");
}

// At f_r = 2.762 the period-1 family has a pitchfork (MODEL.md §5's mirror symmetry). The walk
// from 2.70 lands on the branch born there, which runs up to it and back down as its own mirror
// image: a turn that keeps the count of multipliers outside the unit circle (mirror images
// have the same ones), listed as a branch point since session 47 (a fold before).
TEST_CASE("Fig 13's pitchfork at f_r = 2.762 is located to 1e-6 from two different starts") {
    const ReducedParameters p{5, 60, 0.5, 0.06, 3.0};
    ContinuationOptions o;
    o.to = 2.9;
    o.max_points = 400;
    auto fold_near = [&](double from) {
        o.from = from;
        const ContinuationResult r = continue_orbits(p, o);
        for (const auto& s : r.special)
            if (s.type == SpecialPointType::branch_point && std::abs(s.value - 2.762) < 0.01)
                return s.value;
        return 0.0;
    };
    const double a = fold_near(2.70), b = fold_near(2.73);
    MESSAGE("branch point from 2.70: " << a << ", from 2.73: " << b);
    REQUIRE(a > 0.0);
    REQUIRE(b > 0.0);
    CHECK(std::abs(a - b) < 2e-6);
}

namespace {
const ReducedParameters fig13_row{5, 60, 0.5, 0.06, 3.0};
/// data/scenes/mirror-pair.json: one body between two walls.
const ReducedParameters mirror_pair_row{1, 100, 0.1, 0.6, 1.2};

/// One branch of period k along Fig 13's line from `from` to `to` in f_r.
ContinuationOptions one_branch(double from, double to, int k) {
    ContinuationOptions o;
    o.from = from;
    o.to = to;
    o.period = k;
    o.max_branches = 1;
    return o;
}
} // namespace

TEST_CASE("each continued orbit and special point carries its F_m's error") {
    // On rk4 at a loose tolerance the branch's F_m is off the exact orbit's by 1.8e-6 to 3.5e-6:
    // the error of each point (an independent scheme) covers its distance from the exact scheme's
    // orbit at the same value.
    ContinuationOptions o = one_branch(2.7, 2.75, 1);
    o.orbit.scheme = Scheme::rk4;
    o.orbit.integration_tolerance = 1e-5;
    o.orbit.tolerance = 1e-9;
    const ContinuationResult r = continue_orbits(fig13_row, o);
    REQUIRE(r.points.size() >= 3);
    for (std::size_t i = 0; i < r.points.size(); i += r.points.size() / 3) {
        const BranchPoint& q = r.points[i];
        ReducedParameters at = fig13_row;
        at.f_r = q.value;
        const PeriodicOrbit exact =
            find_periodic_orbit(Dynamics::paper_row(at), OrbitOptions{}, q.state);
        REQUIRE(exact.status == OrbitStatus::converged);
        const double gap = std::abs(q.F_m - exact.F_m);
        CAPTURE(q.value);
        CAPTURE(gap);
        CHECK(gap > 1e-9);
        CHECK(q.F_m_error >= 0.9 * gap);
        CHECK(q.F_m_error <= 1.1 * gap + 1e-9);
    }
    for (const auto& sp : r.special)
        CHECK(std::isfinite(sp.F_m_error));
}

TEST_CASE("a pair of multipliers through -1 together is a period doubling") {
    // Fig 13's period-1 family near its contact-free end: the mirror symmetry makes two equal
    // real multipliers, and they cross -1 together, so det(M + I) keeps its sign; nothing was
    // listed. Newton at fixed f_r on either side of the located value is the independent check.
    const ContinuationResult r = continue_orbits(fig13_row, one_branch(4.15, 4.05, 1));
    const SpecialPoint* doubling = nullptr;
    for (const auto& s : r.special)
        if (s.type == SpecialPointType::period_doubling) doubling = &s;
    REQUIRE(doubling != nullptr);
    MESSAGE("period doubling at f_r = " << doubling->value << " +- " << doubling->value_error);
    auto below_minus_one = [&](double f_r) {
        ReducedParameters p = fig13_row;
        p.f_r = f_r;
        const PeriodicOrbit o =
            find_periodic_orbit_after(Dynamics::paper_row(p), OrbitOptions{}, {}, 300);
        REQUIRE(o.status == OrbitStatus::converged);
        int count = 0;
        for (const auto& mu : o.multipliers)
            count += mu.real() < -1.0 ? 1 : 0;
        return count;
    };
    CHECK(below_minus_one(doubling->value - 1e-4) == 2);
    CHECK(below_minus_one(doubling->value + 1e-4) == 0);
}

TEST_CASE("a branch walked down ends on its end value with no fold there") {
    // The last point, corrected at the end value, had its tangent turned along +f_r: a fold
    // was reported at every downward end (the probe of 2026-11-26: f_r = 2.95002 from 3.0).
    const ContinuationResult r = continue_orbits(fig13_row, one_branch(3.0, 2.95, 1));
    REQUIRE(r.branch_end.size() == 1);
    CHECK(r.branch_end.front() == "reached the end value f_r = 2.95");
    CHECK(r.points.back().value == 2.95);
    CHECK(r.special.empty());
}

TEST_CASE("the pitchfork's turn at f_r = 2.762 located walking through it in both directions") {
    // Forward: up the sheet the transient lands on, through the turn, back down its mirror.
    ContinuationOptions o = one_branch(2.70, 2.9, 1);
    o.max_points = 400;
    const ContinuationResult forward = continue_orbits(fig13_row, o);
    const auto fold_of = [](const ContinuationResult& r) {
        for (const auto& s : r.special)
            if (s.type == SpecialPointType::branch_point && std::abs(s.value - 2.762) < 0.01)
                return s;
        return SpecialPoint{};
    };
    const SpecialPoint a = fold_of(forward);
    REQUIRE(a.value > 0.0);
    // A point of the second sheet, after the fold, below it in f_r.
    const BranchPoint* back = nullptr;
    bool past_fold = false;
    for (const auto& q : forward.points) {
        past_fold = past_fold || q.value > a.value - 1e-4;
        if (past_fold && q.value < a.value - 0.01) {
            back = &q;
            break;
        }
    }
    REQUIRE(back != nullptr);
    // Backward through the fold: from that orbit (no transient), up the second sheet first.
    o.from = back->value;
    o.transient_periods = 0;
    const ContinuationResult backward = continue_orbits(fig13_row, o, back->state);
    REQUIRE(!backward.points.empty());
    CHECK(std::abs(backward.points.front().F_m - back->F_m) < 1e-8);
    const SpecialPoint b = fold_of(backward);
    MESSAGE("fold forward " << a.value << " +- " << a.value_error << ", backward " << b.value
                            << " +- " << b.value_error);
    REQUIRE(b.value > 0.0);
    CHECK(std::abs(a.value - b.value) < 2e-6);
    CHECK(a.value_error <= o.locate_tolerance);
    CHECK(b.value_error <= o.locate_tolerance);
}

TEST_CASE("a corrector thrown out of the parameter range is a failed step, not an error") {
    // Fig 13's period-2 orbit at f_r = 2.3: a Newton update once sent f_r to -27 and the
    // whole continuation died with the model's range error.
    ContinuationResult r;
    REQUIRE_NOTHROW(r = continue_orbits(fig13_row, one_branch(2.3, 2.7, 2)));
    REQUIRE(r.points.size() > 10);
    for (const auto& q : r.points)
        CHECK(q.value > 0.0);
    // The period-2 orbit is stable at the start (the brute-force diagram shows period 2 there).
    CHECK(r.points.front().stable);
    CHECK(r.points.front().period == 2);
}

TEST_CASE("a real multiplier through +1 where the branch goes on is a branch point") {
    // Fig 13's period-1 orbit loses stability at f_r = 2.50158 by a real multiplier through +1
    // with no fold: the mirror symmetry's pitchfork, where a mirror pair of stable orbits is
    // born. The continuation reported only the Neimark-Sacker point at 2.50329.
    const ContinuationResult r = continue_orbits(fig13_row, one_branch(2.48, 2.515, 1));
    std::optional<double> located;
    for (const auto& s : r.special)
        if (s.type == SpecialPointType::branch_point) located = s.value;
    REQUIRE(located.has_value());
    CHECK(*located == doctest::Approx(2.50158).epsilon(2e-5));
    // The branch's points on either side of it, as Newton starts at fixed f_r (orbit.hpp).
    const BranchPoint* before = nullptr;
    const BranchPoint* after = nullptr;
    for (const auto& q : r.points) {
        if (q.value < *located && (!before || q.value > before->value)) before = &q;
        if (q.value > *located && (!after || q.value < after->value)) after = &q;
    }
    REQUIRE(before != nullptr);
    REQUIRE(after != nullptr);
    auto orbit_at = [](double f_r, const std::vector<double>& start) {
        ReducedParameters p = fig13_row;
        p.f_r = f_r;
        const PeriodicOrbit orbit =
            find_periodic_orbit(Dynamics::paper_row(p), OrbitOptions{}, start);
        REQUIRE(orbit.status == OrbitStatus::converged);
        return orbit;
    };
    auto largest_real = [](const PeriodicOrbit& orbit) {
        double largest = -1e300;
        for (const auto& mu : orbit.multipliers)
            if (std::abs(mu.imag()) < 1e-12) largest = std::max(largest, mu.real());
        return largest;
    };
    CHECK(largest_real(orbit_at(*located - 1e-4, before->state)) < 1.0);
    // Past it the branch's orbit has a real multiplier above 1, and a second, stable orbit
    // lies next to it (Newton from the point before the branch point finds it).
    const PeriodicOrbit branch = orbit_at(*located + 4e-4, after->state);
    const PeriodicOrbit born = orbit_at(*located + 4e-4, before->state);
    CHECK(largest_real(branch) > 1.0);
    CHECK(born.stable);
    CHECK(std::abs(born.state[0] - branch.state[0]) > 1e-3);
}

TEST_CASE("a branch says its orbits' minimal period") {
    // Fig 13's stable period-1 orbit (2.786-3.1346) continued as a period-2 orbit: every point
    // repeats after one period. The period-2 orbit from f_r = 2.3 is a genuine one.
    const ContinuationResult twice = continue_orbits(fig13_row, one_branch(2.9, 2.95, 2));
    REQUIRE(!twice.points.empty());
    for (const auto& q : twice.points) {
        CHECK(q.period == 2);
        CHECK(q.minimal_period == 1);
    }
    const ContinuationResult doubled = continue_orbits(fig13_row, one_branch(2.3, 2.31, 2));
    REQUIRE(!doubled.points.empty());
    CHECK(doubled.points.front().minimal_period == 2);
}

namespace {
/// (u, v, parameter) as a traced point.
detail::TracedOrbits::Vector point(double u, double v, double parameter) {
    detail::TracedOrbits::Vector z(3);
    z << u, v, parameter;
    return z;
}
} // namespace

TEST_CASE("traced orbits: a point is compared only with branches whose period its minimal "
          "period divides, at each of their phases") {
    detail::TracedOrbits traced;
    const double step = 0.01;
    // A period-2 branch: state (0.3, 0.1) at phase 0, (-0.3, -0.1) after one period.
    traced.begin_branch(0, 2);
    for (int i = 0; i <= 100; ++i)
        traced.add(point(0.3, 0.1, i * step), {{-0.3, -0.1}, {0.3, 0.1}}, i * step);
    traced.begin_branch(1, 4);                                 // a doubled branch leaving along it
    const auto on_parent = point(0.3, 0.1, 0.505);             // between two points, on their chord
    const auto other_phase = point(-0.3, -0.1, 0.505);         // the same orbits one period on
    CHECK(traced.branch_under(on_parent, 4, 0.0, step) == -1); // period 4 is not on period 2
    CHECK(traced.branch_under(on_parent, 2, 0.0, step) == 0);
    CHECK(traced.branch_under(on_parent, 1, 0.0, step) == 0); // a period-1 orbit can be
    CHECK(traced.branch_under(other_phase, 2, 0.0, step) == 0);
    CHECK(traced.branch_under(on_parent, 0, 0.0, step) == 0); // minimal period unknown: compared
    // Off the chord by more than 0.02 step, though within two steps of its points.
    CHECK(traced.branch_under(point(0.3, 0.1 + 0.03 * step, 0.505), 2, 0.0, step) == -1);
    CHECK(traced.branch_under(point(0.3, 0.1 + 0.01 * step, 0.505), 2, 0.0, step) == 0);
}

TEST_CASE("traced orbits: the current branch is compared only with its points more than 20 "
          "points and 4 steps of arclength back") {
    detail::TracedOrbits traced;
    const double step = 0.01;
    traced.begin_branch(0, 1);
    for (int i = 0; i < 50; ++i)
        traced.add(point(i * step, 0.0, 1.0), {}, i * step);
    const double now = 49 * step;
    // On the chord between points 44 and 45: a neighbour, not a retrace.
    CHECK(traced.branch_under(point(44.5 * step, 0.0, 1.0), 1, now, step) == -1);
    // Between points 28 and 29: 20 points and 20 steps of arclength back, compared.
    CHECK(traced.branch_under(point(28.5 * step, 0.0, 1.0), 1, now, step) == 0);
    // Points 1e-5 apart: at a step of 1e-5 the same point is compared; at a step of 1e-3 (the
    // steps collapsed near a corner) the whole branch lies within 4 steps, so none is.
    traced.begin_branch(1, 1);
    for (int i = 0; i < 50; ++i)
        traced.add(point(i * 1e-5, 1.0, 2.0), {}, i * 1e-5);
    CHECK(traced.branch_under(point(28.5e-5, 1.0, 2.0), 1, 49e-5, 1e-5) == 1);
    CHECK(traced.branch_under(point(28.5e-5, 1.0, 2.0), 1, 49e-5, 1e-3) == -1);
}

TEST_CASE("a branch continued to the end of the parameter's range ends there, written") {
    // eps from 0.5 to 0 on Fig 13's row at f_r = 3: the Jacobian's central difference at eps
    // near 0 asked the model for eps < 0, and the whole continuation died with "model.eps: must
    // be ... in [0, 100], got -9.1e-07".
    ContinuationOptions o;
    o.parameter = SweptParameter::eps;
    o.from = 0.5;
    o.to = 0.0;
    ContinuationResult r;
    REQUIRE_NOTHROW(r = continue_orbits({5, 60, 0.5, 0.06, 3.0}, o));
    double lowest = 1.0;
    for (const auto& q : r.points) {
        CHECK(q.value >= 0.0);
        lowest = std::min(lowest, q.value);
    }
    CHECK(lowest < 1e-3);
    bool range_end = false;
    for (const auto& why : r.branch_end)
        range_end = range_end || why.find("end of the model's range") != std::string::npos;
    CHECK(range_end);
}

TEST_CASE("special points say how well they are located") {
    // From 2.15 to 2.3 the period-1 orbit of Fig 13 passes the wall grazing at 2.1987 (a smooth
    // crossing, located to the tolerance) and then the corner near 2.2445, where the stable
    // orbit ends at a grazing.
    const ContinuationOptions o = one_branch(2.15, 2.3, 1);
    const ContinuationResult r = continue_orbits(fig13_row, o);
    bool wall_grazing = false;
    for (const auto& s : r.special) {
        CHECK(s.value_error >= 0.0);
        if (s.type == SpecialPointType::grazing && std::abs(s.value - 2.1987) < 1e-3) {
            wall_grazing = true;
            CHECK(s.value_error <= o.locate_tolerance);
        }
    }
    CHECK(wall_grazing);
}

TEST_CASE("a start or end value outside the model's range names the option that carried it") {
    ContinuationOptions o = one_branch(-1.0, 3.0, 1);
    CHECK_THROWS_WITH_AS(continue_orbits(fig13_row, o), doctest::Contains("from: excitation.f_r"),
                         std::invalid_argument);
    o = one_branch(2.0, std::numeric_limits<double>::infinity(), 1);
    CHECK_THROWS_WITH_AS(continue_orbits(fig13_row, o), doctest::Contains("to: excitation.f_r"),
                         std::invalid_argument);
    // In the model's range, but one forcing period would take 4e301 steps.
    o = one_branch(1e-300, 3.0, 1);
    CHECK_THROWS_WITH_AS(continue_orbits(fig13_row, o),
                         doctest::Contains("from: excitation.f_r: one forcing period"),
                         std::invalid_argument);
    o = one_branch(3.0, 1e-300, 1);
    CHECK_THROWS_WITH_AS(continue_orbits(fig13_row, o),
                         doctest::Contains("to: excitation.f_r: one forcing period"),
                         std::invalid_argument);
}

TEST_CASE("a line whose branches may take beyond run.max_work is refused before it runs") {
    // A hostile probe (helper-85): steps of 1e-6 over 1 .. 4.5, a million points a branch,
    // every shooting within the limit; it ran on for hours (about 230 points a second).
    const ReducedParameters row{3, 100, 0.5, 0.1, 1.5};
    ContinuationOptions o;
    o.from = 1.0;
    o.to = 4.5;
    o.step = o.max_step = 1e-6;
    o.max_points = 1'000'000;
    CHECK_THROWS_WITH_AS(continue_orbits(row, o),
                         doctest::Contains("run.max_work: walking the line may take"),
                         std::invalid_argument);
    // One branch of steps that cover the line in 3.5e6 points is still 3e6 shootings too many
    // for a 1e9 limit; the default steps (0.01 .. 0.05) are not.
    o.max_branches = 1;
    o.orbit.max_work = 1e9;
    CHECK_THROWS_AS(continue_orbits(row, o), std::invalid_argument);
    o.step = 0.01;
    o.max_step = 0.05;
    o.max_points = 3;
    CHECK_NOTHROW(continue_orbits(row, o));
}

TEST_CASE("the period-1 family turns at its grazing corner onto the other sheet and follows it") {
    // Fig 13's period-1 family from 2.15 passes the fold at 3.3044, winds down to a corner at
    // 2.99783 where contacts 2 and 3 graze, and turns there onto a sheet on which they stay
    // open. The arclength corrector used to land on that sheet from 3.01871 (0.023 away in the
    // state), skip both sheets down to the corner, walk the far one back into the corner and
    // end "back onto itself": the far sheet above 3.00128 was never traced. Numbers from an
    // independent implementation (RK4 with switches located to round-off, Newton shooting;
    // review of 2026-11-27): at 3.00128 the near sheet's orbit has |mu| 4.75, the far one's
    // 0.579; the far sheet is stable up to a Neimark-Sacker at 3.065158.
    const ContinuationResult r = continue_orbits(fig13_row, one_branch(2.15, 4.5, 1));
    REQUIRE(r.branch_end.size() == 1);
    CHECK(r.branch_end.front().rfind("reached the end value", 0) == 0);
    double top = 0.0;
    bool near_sheet = false, far_sheet = false;
    for (const auto& q : r.points) {
        top = std::max(top, q.value);
        if (q.value < 2.9975 || q.value > 3.0035) continue;
        near_sheet = near_sheet || q.max_multiplier > 4.0;
        far_sheet = far_sheet || (q.stable && q.max_multiplier < 0.7);
    }
    CHECK(near_sheet);
    CHECK(far_sheet);
    CHECK(top == doctest::Approx(4.5));
    bool torus = false;
    for (const auto& sp : r.special)
        if (sp.type == SpecialPointType::neimark_sacker &&
            std::abs(sp.value - 3.065158) <= sp.value_error + 1e-6)
            torus = true;
    CHECK(torus);
    // The far sheet between the corner and that point, stable, every orbit of it below the
    // near sheet's F_m at the corner (0.1727).
    long on_far = 0;
    for (const auto& q : r.points)
        if (q.value > 3.01 && q.value < 3.06 && q.stable && q.F_m < 0.17) ++on_far;
    MESSAGE(r.points.size() << " orbits, " << on_far << " on the far sheet in 3.01-3.06");
    CHECK(on_far >= 3);
}

TEST_CASE("a fold is located where the branch turns, beyond both ends of its bracket") {
    // The independent implementation of the review of 2026-11-27 puts Fig 13's fold over the
    // clearance (f_r = 3) at e_r = 0.0738587; the bracket's width alone, narrow in e_r where
    // both its ends had come to one value, reported 0.07385728 +- 5.4e-7.
    ContinuationOptions o = one_branch(0.02, 0.5, 1);
    o.parameter = SweptParameter::e_r;
    ReducedParameters row = fig13_row;
    row.e_r = 0.02;
    const ContinuationResult r = continue_orbits(row, o);
    bool found = false;
    for (const auto& sp : r.special)
        if (sp.type == SpecialPointType::fold && std::abs(sp.value - 0.0738587) < 1e-5) {
            MESSAGE("fold at " << sp.value << " +- " << sp.value_error);
            CHECK(std::abs(sp.value - 0.0738587) <= sp.value_error + 1e-7);
            found = true;
        }
    CHECK(found);
}

TEST_CASE("the period-2 loop of Fig 13's line is traced round once, both of its sheets") {
    // The period-2 orbits born where period 1 loses stability near 2.254 lie on a closed loop
    // of two sheets joined at folds near 2.2573 and 2.4651. Near a fold the sheets come within
    // a step of each other (0.04 apart at 2.4557); a branch that took that for coming back
    // onto itself stopped there and lost the lower sheet. The third branch, switched onto
    // the same loop where period 1 loses stability again near 2.467, follows its orbits at
    // the other phase (each state one period on) and ends once it is seen to be on them.
    ContinuationOptions o = one_branch(2.2, 2.5, 1);
    o.follow_doublings = true;
    o.max_branches = 3;
    const ContinuationResult r = continue_orbits(fig13_row, o);
    REQUIRE(r.branch_end.size() == 3);
    CHECK(r.branch_end[1].rfind("came back onto itself", 0) == 0);
    CHECK(r.branch_end[2].rfind("came onto branch 1", 0) == 0);
    std::vector<const BranchPoint*> loop;
    std::size_t again = 0;
    for (const auto& q : r.points) {
        if (q.branch == 1) loop.push_back(&q);
        if (q.branch == 2) ++again;
    }
    // It starts on the loop: it stops within a few points (it ran 25, for the arclength of 20
    // maximal steps, while every other branch was ignored near a branch's start), so the
    // loop's special points are listed once.
    MESSAGE("the third branch ran " << again << " points");
    CHECK(again <= 6);
    for (const auto& s : r.special)
        CHECK(s.branch != 2);
    REQUIRE(loop.size() > 10);
    // Round once: it crosses f_r = 2.4 twice (once per sheet) and ends next to its start.
    std::vector<const BranchPoint*> at_2_4;
    for (std::size_t i = 1; i < loop.size(); ++i)
        if ((loop[i - 1]->value - 2.4) * (loop[i]->value - 2.4) <= 0.0) at_2_4.push_back(loop[i]);
    REQUIRE(at_2_4.size() == 2);
    CHECK(std::abs(loop.back()->value - loop.front()->value) < 0.01);
    // The two crossings are two period-2 orbits, each confirmed by Newton from scratch.
    std::vector<PeriodicOrbit> sheets;
    for (const BranchPoint* q : at_2_4) {
        ReducedParameters p = fig13_row;
        p.f_r = q->value;
        OrbitOptions orbit;
        orbit.period = 2;
        sheets.push_back(find_periodic_orbit(Dynamics::paper_row(p), orbit, q->state));
        CHECK(sheets.back().status == OrbitStatus::converged);
        CHECK(sheets.back().minimal_period == 2);
    }
    CHECK(std::abs(sheets[0].state[0] - sheets[1].state[0]) > 1e-3);
    // Its upper fold: the independent implementation finds a period-2 orbit at 2.4650719, which
    // the fold must lie beyond (it was reported at 2.46507132 +- 2.5e-7).
    bool fold = false;
    for (const auto& sp : r.special)
        if (sp.type == SpecialPointType::fold && std::abs(sp.value - 2.4651) < 1e-3) {
            CHECK(sp.value + sp.value_error >= 2.4650719);
            fold = true;
        }
    CHECK(fold);
}

TEST_CASE("--follow-doublings switches at the grazing corner where period 1 loses stability") {
    // Fig 13's period-1 orbit loses stability near f_r = 2.254 (a grazing corner at 2.2453
    // until the switch search looked inside steps, 2026-11-25; now a Neimark-Sacker at 2.25398
    // among grazings at 2.258-2.272): a period-2 branch is reached from there, and its orbits
    // are checked independently.
    ContinuationOptions o = one_branch(2.2, 2.3, 1);
    o.follow_doublings = true;
    o.max_branches = 2;
    const ContinuationResult r = continue_orbits(fig13_row, o);
    const BranchPoint* doubled = nullptr;
    for (const auto& q : r.points)
        if (q.period == 2 && !doubled) doubled = &q;
    REQUIRE(doubled != nullptr);
    CHECK(doubled->value > 2.2452);
    CHECK(doubled->value < 2.27);
    // Newton on the 2-map from that state, at that value, from scratch: a period-2 orbit, not
    // a period-1 orbit visited twice.
    ReducedParameters q = fig13_row;
    q.f_r = doubled->value;
    const Dynamics dyn = Dynamics::paper_row(q);
    OrbitOptions orbit;
    orbit.period = 2;
    const PeriodicOrbit found = find_periodic_orbit(dyn, orbit, doubled->state);
    CHECK(found.status == OrbitStatus::converged);
    CHECK(found.minimal_period == 2);
    CHECK(std::abs(found.F_m - doubled->F_m) < 1e-6);
}

TEST_CASE("a line in fc that ends beyond the exact scheme's stiffest contacts is refused before "
          "it runs") {
    // It ran every value below the limit, then threw at the first above, losing all of it.
    ContinuationOptions o;
    o.parameter = SweptParameter::fc;
    o.from = 1.0e8;
    o.to = 3.0e8;
    const ReducedParameters row{2, 1e8, 0.5, 0.3, 5.0};
    bool asked = false;
    CHECK_THROWS_WITH_AS(continue_orbits(row, o, {},
                                         [&](double) {
                                             asked = true;
                                             return true;
                                         }),
                         doctest::Contains("scheme: exact takes contacts"), std::invalid_argument);
    CHECK_FALSE(asked);
}

TEST_CASE("branches found and not traced for max_branches are listed, not dropped") {
    // --follow-doublings with --max-branches 1 wrote what a run without it wrote, and said
    // nothing of the two period-2 branches it found (the probe of 2026-11-27).
    ContinuationOptions o = one_branch(2.15, 2.6, 1);
    o.follow_doublings = true;
    const ContinuationResult r = continue_orbits(fig13_row, o);
    REQUIRE(r.branch_end.size() == 1);
    REQUIRE(r.unfollowed.size() == 2);
    CHECK(r.unfollowed.front().rfind("period 2 from f_r = 2.25", 0) == 0);
    o.max_branches = 12;
    o.to = 2.3;
    CHECK(continue_orbits(fig13_row, o).unfollowed.empty());
}

TEST_CASE("the progress of a branch that turns back at a fold never goes back") {
    // From 3.0 up, Fig 13's period-1 family folds at 3.3044 and walks back down: its fraction
    // of the line fell (46.8 -> 33.9 % on the whole line, the probe of 2026-11-27).
    std::vector<double> fractions;
    const ContinuationOptions o = one_branch(3.0, 3.4, 1);
    const ContinuationResult r = continue_orbits(fig13_row, o, {}, [&](double f) {
        fractions.push_back(f);
        return true;
    });
    double top = 0.0;
    for (const auto& q : r.points)
        top = std::max(top, q.value);
    REQUIRE(top > 3.3);
    REQUIRE(r.points.back().value < 3.25); // it did walk back
    REQUIRE(!fractions.empty());
    for (std::size_t i = 1; i < fractions.size(); ++i)
        CHECK(fractions[i] >= fractions[i - 1]);
}

TEST_CASE("a branch point the walk steps across onto the other branch is listed once") {
    // mirror-pair.json: one body between two walls. An independent shooting code (exact
    // propagator, switches to round-off; 2026-11-27) puts the symmetric orbit's supercritical
    // pitchfork at f_r = 1.2161160180, a stable mirror pair below it. Walking up the pair, the
    // step across it lands on the symmetric orbit (unstable below, stable above), and both the
    // bracket across the two branches and the next one along the symmetric orbit hold the
    // point: it was listed at 1.21611595 +- 1.9e-8 (6.5e-8 off) and 1.21611623 +- 6.0e-7.
    const ContinuationResult r = continue_orbits(mirror_pair_row, one_branch(1.2, 1.3, 1));
    int listed = 0;
    for (const auto& s : r.special) {
        if (s.type != SpecialPointType::branch_point) continue;
        ++listed;
        CAPTURE(s.value);
        CAPTURE(s.value_error);
        CHECK(std::abs(s.value - 1.2161160180) <= s.value_error);
        CHECK(s.value_error < 1e-5);
        // Both branches meet there with the symmetric orbit's F_m, 0.779849.
        CHECK(std::abs(s.F_m - 0.779849) <= s.F_m_error + 1e-6);
    }
    CHECK(listed == 1);
}

TEST_CASE(
    "a branch turning at a pitchfork into its mirror image lists a branch point, not a fold") {
    // mirror-pair.json walked in short steps up the stable mirror pair: it turns at the
    // symmetric orbit's pitchfork (1.2161160180, F_m 0.779849: an independent shooting code)
    // into its mirror image, its multiplier touching +1 from below. Listed as a fold at
    // 1.21611613 +- 2.9e-8 (1.1e-7 off) before; the fold test and the branch test also split
    // it into a fold and a branch point where the multiplier read 1 + 1e-7.
    ContinuationOptions o = one_branch(1.214, 1.2165, 1);
    o.step = 0.002;
    o.max_step = 0.004;
    o.max_points = 400;
    const ContinuationResult r = continue_orbits(mirror_pair_row, o);
    int listed = 0;
    for (const auto& s : r.special) {
        CHECK(s.type != SpecialPointType::fold);
        if (s.type != SpecialPointType::branch_point) continue;
        ++listed;
        CAPTURE(s.value);
        CHECK(std::abs(s.value - 1.2161160180) <= s.value_error);
        CHECK(s.value_error < 1e-5);
        CHECK(std::abs(s.F_m - 0.779849) <= s.F_m_error + 1e-6);
    }
    CHECK(listed == 1);
}

TEST_CASE("a turn that no orbit goes on past is a fold, and a turn at a pitchfork a branch "
          "point, whatever the multipliers outside the unit circle") {
    // An independent review (helper-84: SciPy DOP853 shooting with the switches located, written
    // from MODEL.md) on one body, fc 100, eps 0.2, e_r 0.05, walked down from f_r = 3:
    // - at 2.62439229 two asymmetric orbits merge (Newton finds both above, none below): a
    //   fold. A multiplier crosses -1 in the same step (the doubling at 2.62490), so the count
    //   outside the unit circle stayed 1 and the turn was listed as a branch point;
    // - at about 1.477925 the symmetric family, monotone in f_r, has a multiplier through +1:
    //   a pitchfork. The walk came down the branch born there and turned off onto the
    //   symmetric family, and the turn was listed as a fold beside the branch point.
    const ReducedParameters row{1, 100, 0.2, 0.05, 0.5};
    ContinuationOptions o;
    o.from = 3.0;
    o.to = 1.45;
    const ContinuationResult r = continue_orbits(row, o);
    int folds = 0, branch_points = 0;
    for (const auto& s : r.special) {
        CAPTURE(s.value);
        CAPTURE(s.value_error);
        if (std::abs(s.value - 2.62439229) < 1e-4) {
            CHECK(s.type != SpecialPointType::branch_point);
            if (s.type != SpecialPointType::fold) continue;
            ++folds;
            CHECK(std::abs(s.value - 2.62439229) <= s.value_error + 1e-7);
        }
        if (std::abs(s.value - 1.477925) < 1e-4) {
            CHECK(s.type != SpecialPointType::fold);
            if (s.type != SpecialPointType::branch_point) continue;
            ++branch_points;
            CHECK(std::abs(s.value - 1.477925) <= s.value_error + 2e-6);
        }
    }
    CHECK(folds == 1);
    CHECK(branch_points == 1);
    // Between the fold and the doubling at 2.62490 the branch is stable; both fell in one step,
    // and branch.csv held no orbit of that stretch. A step with two kinds of special point in
    // it is now halved.
    CHECK(std::any_of(r.points.begin(), r.points.end(), [](const BranchPoint& q) {
        return q.stable && q.value > 2.62439229 + 1e-6 && q.value < 2.62490 - 1e-6;
    }));
}

TEST_CASE("a restart beyond a branch's end traces the skipped stretch back") {
    // From 2.7 the mirror pair's branch turns at the pitchfork (2.762) and the walk restarts a
    // step (0.01) beyond, at 2.772, on the symmetric orbit. Walking on from there only, the
    // symmetric orbit's Neimark-Sacker point at 2.77011 was not listed; with a step of 0.002,
    // or walking down from 2.8, it was (2.77011171, a helper's probe, 2026-11-27).
    ContinuationOptions up;
    up.from = 2.7;
    up.to = 2.8;
    ContinuationOptions down = up;
    std::swap(down.from, down.to);
    auto neimark_sacker = [](const ContinuationResult& r) -> std::optional<SpecialPoint> {
        for (const auto& s : r.special)
            if (s.type == SpecialPointType::neimark_sacker && std::abs(s.value - 2.7701) < 1e-3)
                return s;
        return std::nullopt;
    };
    const ContinuationResult r = continue_orbits(fig13_row, up);
    const auto found = neimark_sacker(r);
    REQUIRE(found);
    CHECK(std::any_of(r.branch_end.begin(), r.branch_end.end(), [](const std::string& why) {
        return why.find("where the branch it restarts ended") != std::string::npos;
    }));
    const auto reference = neimark_sacker(continue_orbits(fig13_row, down));
    REQUIRE(reference);
    MESSAGE("up " << found->value << " +- " << found->value_error << ", down " << reference->value
                  << " +- " << reference->value_error);
    CHECK(std::abs(found->value - reference->value) <= found->value_error + reference->value_error);
    CHECK(std::abs(found->value - 2.77011171) <= found->value_error + 1e-7);
    // A step beyond that lies past the end value restarts at the end value, walked back only:
    // with --to 2.771 nothing was traced beyond the pitchfork (a second reader, 2026-11-27).
    ContinuationOptions short_line = up;
    short_line.to = 2.771;
    const auto near_end = neimark_sacker(continue_orbits(fig13_row, short_line));
    REQUIRE(near_end);
    CHECK(std::abs(near_end->value - reference->value) <=
          near_end->value_error + reference->value_error);
}
