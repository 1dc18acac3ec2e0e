#include "gapchain/accuracy.hpp"
#include "gapchain/simulation.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

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
    // The reference's error covers an independent scheme's answer (rk8pd at 1e-12).
    RunOptions rk8pd;
    rk8pd.scheme = Scheme::rk8pd;
    rk8pd.tolerance = 1e-12;
    rk8pd.periods = o.periods;
    rk8pd.transient_periods = 0;
    rk8pd.stop_at_steady_state = false;
    rk8pd.estimate_error = false;
    rk8pd.multistability_check = false;
    const double independent = simulate(dyn, rk8pd).F_m;
    MESSAGE("reference " << study.F_m_reference << " +- " << study.F_m_reference_error << ", rk8pd "
                         << independent);
    CHECK(std::abs(study.F_m_reference - independent) <= study.F_m_reference_error);
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
    // A tolerance listed twice ran twice and wrote duplicate rows.
    WorkPrecisionOptions twice;
    twice.tolerances = {1e-3, 1e-4, 1e-3};
    CHECK_THROWS_WITH_AS(work_precision(dyn, twice),
                         doctest::Contains("tolerances: 0.001 is listed twice"),
                         std::invalid_argument);
}

namespace {
// A short study of one scheme on a small row's options.
WorkPrecisionOptions short_study(Scheme scheme, std::vector<double> tolerances, long periods,
                                 int repeats) {
    WorkPrecisionOptions o;
    o.schemes = {scheme};
    o.tolerances = std::move(tolerances);
    o.periods = periods;
    o.repeats = repeats;
    return o;
}
} // namespace

TEST_CASE("a work-precision study runs only the schemes asked for, within run.max_work") {
    const Dynamics dyn = Dynamics::paper_row({3, 50, 0.5, 0.3, 1.1});
    WorkPrecisionOptions o = short_study(Scheme::exact, {1e-3, 1e-6}, 5, 1);
    // unsplit_too stays on: it adds the unsplit runs of central_difference and rk4 only when
    // they are among the schemes (they ran whatever was asked before).
    const WorkPrecision study = work_precision(dyn, o);
    CHECK(study.points.size() == 2);
    for (const WorkPrecisionPoint& p : study.points)
        CHECK((p.scheme == Scheme::exact && p.split));
    o.schemes = {Scheme::rk4};
    CHECK(work_precision(dyn, o).points.size() == 4);
    // The whole study is checked before it starts (gapchain-accuracy accepted 3.4 h).
    o.max_work = 1e4;
    CHECK_THROWS_WITH_AS(work_precision(dyn, o), doctest::Contains("run.max_work: this study"),
                         std::invalid_argument);
    // Its reference is the exact propagator: the row's size is named, whatever the schemes.
    o.max_work = 3e10;
    CHECK_THROWS_WITH_AS(
        work_precision(Dynamics::paper_row({65, 50, 0.5, 0.3, 1.1}), o),
        doctest::Contains("reference is the exact propagator, which cannot run this row: exact "
                          "takes rows of up to 64 bodies"),
        std::invalid_argument);
    // And it does not advise another scheme, which cannot serve as the reference.
    try {
        (void)work_precision(Dynamics::paper_row({65, 50, 0.5, 0.3, 1.1}), o);
        FAIL("the 65-body row was accepted");
    } catch (const std::invalid_argument& e) {
        CHECK(std::string(e.what()).find("use rk4") == std::string::npos);
    }
}

TEST_CASE("a work-precision study reports its fraction done and stops when progress says so") {
    const Dynamics dyn = Dynamics::paper_row({3, 50, 0.5, 0.3, 1.1});
    WorkPrecisionOptions o = short_study(Scheme::rk4, {1e-3, 1e-5}, 10, 2);
    o.unsplit_too = false;
    std::vector<double> seen;
    const WorkPrecision whole = work_precision(dyn, o, [&](double f) {
        seen.push_back(f);
        return true;
    });
    CHECK_FALSE(whole.cancelled);
    CHECK(whole.points.size() == 2);
    REQUIRE(!seen.empty());
    CHECK(std::is_sorted(seen.begin(), seen.end()));
    CHECK(seen.front() >= 0.0);
    CHECK(seen.back() == doctest::Approx(1.0)); // 5 runs: the reference and 2 x 2
    // Stopped inside the fourth run of five (the first repeat of the second tolerance, from 0.6
    // to 0.8 of the study): the first tolerance's point is kept.
    const WorkPrecision stopped = work_precision(dyn, o, [](double f) { return f < 0.7; });
    CHECK(stopped.cancelled);
    CHECK(stopped.points.size() == 1);
}
