#include "gapchain/continuation.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

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
    CHECK(r.branch_end.front() == "left the parameter range");
    for (const auto& point : r.points) {
        CHECK(point.stable);
        CHECK(point.F_m == 0.0);
        CHECK(point.max_multiplier ==
              doctest::Approx(std::exp(-2 * pi * eps / point.value)).epsilon(1e-8));
    }
}

TEST_CASE("Fig 13's fold at f_r = 2.762 is located to 1e-6 from two different starts") {
    const ReducedParameters p{5, 60, 0.5, 0.06, 3.0};
    ContinuationOptions o;
    o.to = 2.9;
    o.max_points = 400;
    auto fold_near = [&](double from) {
        o.from = from;
        const ContinuationResult r = continue_orbits(p, o);
        for (const auto& s : r.special)
            if (s.type == SpecialPointType::fold && std::abs(s.value - 2.762) < 0.01)
                return s.value;
        return 0.0;
    };
    const double a = fold_near(2.70), b = fold_near(2.73);
    MESSAGE("fold from 2.70: " << a << ", from 2.73: " << b);
    REQUIRE(a > 0.0);
    REQUIRE(b > 0.0);
    CHECK(std::abs(a - b) < 2e-6);
}
