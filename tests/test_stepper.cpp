#include "gapchain/simulation.hpp"
#include "gapchain/stepper.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>
#include <string>

using namespace gapchain;

namespace {
double fm_at(const Dynamics& dyn, Scheme s, double step) {
    RunOptions o;
    o.scheme = s;
    o.step = step;
    o.periods = 60;
    o.estimate_error = false;
    return simulate(dyn, o).F_m;
}
} // namespace

TEST_CASE("measured convergence order of F_m: central difference 2, rk4 4") {
    // Smooth periodic scene with contacts (the Fig 5 scene). Three steps h, h/2, h/4 give
    // p = log2(|F(h) - F(h/2)| / |F(h/2) - F(h/4)|) without any reference value.
    const ReducedParameters p{5, 100, 0.5, 0.5, 1.0};
    const Dynamics dyn(Chain::homogeneous(p), {p.f_r, 1.0});
    const double w = dyn.max_angular_frequency();
    auto order = [&](Scheme s, double hw) {
        const double f1 = fm_at(dyn, s, hw / w);
        const double f2 = fm_at(dyn, s, hw / 2 / w);
        const double f4 = fm_at(dyn, s, hw / 4 / w);
        return std::log2(std::abs(f1 - f2) / std::abs(f2 - f4));
    };
    const double p_cd = order(Scheme::central_difference, 0.2);
    const double p_rk4 = order(Scheme::rk4, 0.4);
    MESSAGE("central difference order " << p_cd << ", rk4 order " << p_rk4);
    CHECK(p_cd == doctest::Approx(2.0).epsilon(0.1));
    CHECK(p_rk4 == doctest::Approx(4.0).epsilon(0.15));
}

TEST_CASE("a user step beyond the stability bound is refused with the bound") {
    const ReducedParameters p{5, 2000, 0.5, 0.24, 1.0};
    const Dynamics dyn(Chain::homogeneous(p), {p.f_r, 1.0});
    const double limit = 2.0 / dyn.max_angular_frequency();
    try {
        (void)plan_step(dyn, Scheme::central_difference, 1e-4, 1.01 * limit);
        FAIL("no exception");
    } catch (const std::invalid_argument& e) {
        const std::string m = e.what();
        CHECK(m.find("run.step") != std::string::npos);
        CHECK(m.find("unstable") != std::string::npos);
    }
    CHECK_NOTHROW((void)plan_step(dyn, Scheme::central_difference, 1e-4, 0.9 * limit));
}

TEST_CASE("the planned step fits the forcing period and tightens with the tolerance") {
    const ReducedParameters p{3, 60, 0.5, 0.1, 2.7};
    const Dynamics dyn(Chain::homogeneous(p), {p.f_r, 1.0});
    const StepPlan loose = plan_step(dyn, Scheme::rk4, 1e-3);
    const StepPlan tight = plan_step(dyn, Scheme::rk4, 1e-8);
    CHECK(loose.step * loose.steps_per_period == doctest::Approx(dyn.period()).epsilon(1e-14));
    CHECK(tight.step < loose.step);
    CHECK(tight.step * dyn.max_angular_frequency() < traits(Scheme::rk4).stability_limit);
    CHECK(plan_step(dyn, Scheme::automatic, 1e-4).scheme == Scheme::rk4);
    CHECK_THROWS_AS(parse_scheme("euler"), std::invalid_argument);
}
