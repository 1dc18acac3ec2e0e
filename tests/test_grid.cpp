#include "gapchain/grid.hpp"

#include <doctest/doctest.h>

#include <cmath>

#include <stdexcept>

using namespace gapchain;

TEST_CASE("linspace: exact ends and exact integer ranges") {
    const auto v = linspace(0.1, 0.7, 7);
    REQUIRE(v.size() == 7);
    CHECK(v.front() == 0.1);
    CHECK(v.back() == 0.7);
    // An integer range stays integral (the naive from + (to - from) k / (n - 1) gives
    // 14.000000000000002 at k = 13 for [1, 100, 100]).
    const auto seeds = linspace(1, 100, 100);
    for (int k = 0; k < 100; ++k)
        CHECK(seeds[k] == static_cast<double>(k + 1));
    CHECK(linspace(3.5, 9.0, 1) == std::vector<double>{3.5});
}

TEST_CASE("logspace: decades") {
    const auto v = logspace(1.0, 1000.0, 4);
    REQUIRE(v.size() == 4);
    CHECK(v[0] == 1.0);
    CHECK(v[1] == doctest::Approx(10.0).epsilon(1e-15));
    CHECK(v[2] == doctest::Approx(100.0).epsilon(1e-15));
    CHECK(v[3] == doctest::Approx(1000.0).epsilon(1e-15));
    // Ends whose ratio overflows: every inner value came out inf.
    const auto wide = logspace(1e-303, 1e6, 3);
    CHECK(wide[1] == doctest::Approx(std::pow(10.0, -148.5)).epsilon(1e-12));
}

TEST_CASE("linspace and logspace refuse empty or non-finite ranges") {
    CHECK_THROWS_AS(linspace(0, 1, 0), std::invalid_argument);
    CHECK_THROWS_AS(linspace(0, 1.0 / 0.0, 3), std::invalid_argument);
    CHECK_THROWS_AS(logspace(0, 1, 3), std::invalid_argument);
}

TEST_CASE("require_line: one value needs equal ends, several need distinct ones") {
    CHECK_NOTHROW(require_line(3.2, 3.2, 1));
    CHECK_NOTHROW(require_line(2.0, 4.5, 2));
    CHECK_THROWS_WITH_AS(require_line(2.0, 4.5, 1), doctest::Contains("steps: one value needs"),
                         std::invalid_argument);
    CHECK_THROWS_WITH_AS(require_line(3.0, 3.0, 5), doctest::Contains("got 5"),
                         std::invalid_argument);
    // Two doubles apart: five steps would run 3 four times (and the message shows the ends).
    const double next = std::nextafter(std::nextafter(3.0, 4.0), 4.0);
    CHECK_THROWS_WITH_AS(require_line(3.0, next, 5),
                         doctest::Contains("steps: from 3 to 3.000000000000001 in 5 steps repeats"),
                         std::invalid_argument);
    // As many steps as doubles from end to end: every value its own (an estimate of the
    // spacing refused these).
    CHECK_NOTHROW(require_line(3.0, std::nextafter(3.0, 4.0), 2));
    CHECK_NOTHROW(require_line(3.0, next, 3));
    // Where each value is its own double, the line stands.
    CHECK_NOTHROW(require_line(3.0, 3.0 + 1e-12, 5));
    CHECK_NOTHROW(require_line(0.0, 1e-300, 10000));
}

TEST_CASE("an end given as -0 is 0") {
    // It was written "-0" in the CSVs and -0.0 in the JSON (a map's e_r row, a diagram's value).
    CHECK_FALSE(std::signbit(linspace(-0.0, 1.0, 3).front()));
    CHECK_FALSE(std::signbit(linspace(-0.0, -0.0, 1).front()));
    CHECK_FALSE(std::signbit(linspace(-1.0, -0.0, 2).back()));
}
