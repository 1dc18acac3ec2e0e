#include "gapchain/classify.hpp"

#include "gapchain/report.hpp"

#include <doctest/doctest.h>

using namespace gapchain;

TEST_CASE("along the Fig 13 line: periodic in 2.7 < f_r < 3.1, chaotic inside 3.2 < f_r < 3.55") {
    const ClassifyOptions o;
    // Points clear of the narrow windows the bifurcation diagram shows (a non-periodic patch at
    // 2.746-2.767 and a period-3 window at 3.24-3.25, docs/bifurcation.md).
    for (double f_r : {2.8, 2.875, 2.95, 3.025}) {
        const Classification c = classify({5, 60, 0.5, 0.06, f_r}, o);
        CAPTURE(f_r);
        CHECK(c.regime == Regime::periodic);
        CHECK(c.period == 1);
        CHECK(c.lambda_max < 0.0);
    }
    int chaotic = 0;
    for (double f_r : {3.2, 3.275, 3.3, 3.35}) {
        const Classification c = classify({5, 60, 0.5, 0.06, f_r}, o);
        CAPTURE(f_r);
        CHECK(c.regime == Regime::chaotic);
        chaotic += c.regime == Regime::chaotic;
        CHECK(c.distinct_points > 100);
    }
    CHECK(chaotic == 4);
}

TEST_CASE("no contact above the eq (20) boundary") {
    const Classification c = classify({5, 60, 0.5, 1.4, 1.0}, ClassifyOptions{});
    CHECK(c.regime == Regime::no_contact);
    CHECK(c.F_m == 0.0);
}

TEST_CASE("a regime map does not depend on the number of threads") {
    const std::vector<double> e_r{0.03, 0.1, 0.5};
    const std::vector<double> f_r{1.0, 2.4, 3.3, 4.6};
    ClassifyOptions o;
    o.record_periods = 100;
    const RegimeMap one = regime_map({5, 60, 0.5, 0.06, 1.0}, e_r, f_r, o, 1);
    const RegimeMap two = regime_map({5, 60, 0.5, 0.06, 1.0}, e_r, f_r, o, 2);
    CHECK(map_csv(one) == map_csv(two));
    CHECK(one.cells.size() == 12);
}

TEST_CASE("a periodic label is confirmed by Newton: the period-3 orbit the repetition test read "
          "as 6") {
    // Issue 17: a multiplier near -1 makes the approach alternate every 3 periods.
    const ReducedParameters p{3, 200, 0.5, 0.03, 5.5};
    ClassifyOptions o;
    const Classification c = classify(p, o);
    REQUIRE(c.regime == Regime::periodic);
    CHECK(c.newton_confirmed);
    CHECK(c.period == 3);
    CHECK(c.max_multiplier == doctest::Approx(0.7313).epsilon(1e-3));
    o.confirm_by_newton = false;
    CHECK(classify(p, o).period == 6); // the repetition test alone, as before
}
