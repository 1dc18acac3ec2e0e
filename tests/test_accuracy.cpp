#include "gapchain/accuracy.hpp"

#include <doctest/doctest.h>

#include <stdexcept>

using namespace gapchain;

TEST_CASE("work-precision study: errors fall with the tolerance, exact is its own reference") {
    const ReducedParameters p{3, 50, 0.5, 0.3, 1.1};
    const Dynamics dyn = Dynamics::paper_row(p);
    WorkPrecisionOptions o;
    o.schemes = {Scheme::rk4, Scheme::exact};
    o.tolerances = {1e-3, 1e-5, 1e-7};
    o.periods = 10;
    o.repeats = 1;
    o.unsplit_too = false;
    const WorkPrecision study = work_precision(dyn, o);
    REQUIRE(study.points.size() == 6);
    CHECK(study.F_m_reference > 0.0);
    // rk4: the error shrinks as the tolerance tightens (by at least 10x over the ladder).
    CHECK(study.points[2].F_m_error < 0.1 * study.points[0].F_m_error);
    CHECK(study.points[2].final_error < study.points[0].final_error);
    // exact against itself at half the interval: round-off only.
    for (int k = 3; k < 6; ++k) {
        CHECK(study.points[k].F_m_error < 1e-11);
        CHECK(study.points[k].final_error < 1e-11);
    }
    const auto best = fastest_for(study, 1e-6);
    REQUIRE(best.has_value());
    CHECK(best->F_m_error <= 1e-6);
    CHECK_THROWS_AS(work_precision(dyn, WorkPrecisionOptions{{Scheme::automatic}}),
                    std::invalid_argument);
}
