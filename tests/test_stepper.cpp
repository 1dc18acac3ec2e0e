#include "gapchain/orbit.hpp"
#include "gapchain/simulation.hpp"
#include "gapchain/stepper.hpp"

#include <doctest/doctest.h>

#include "gapchain/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
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
    const Dynamics dyn = Dynamics::paper_row(p);
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
    const Dynamics dyn = Dynamics::paper_row(p);
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

TEST_CASE("the exact scheme is refused for contacts stiffer than it resolves, and auto does not "
          "choose it there") {
    // Against rk8pd at 1e-9 (Nm = 3, e_r = 0): exact's F_m was off by 6e-6 at fc = 1e8 and by
    // 62 % at fc = 3e8 (with an error bar that said so only by its size).
    const Dynamics stiff = Dynamics::paper_row({3, 3e8, 0.5, 0.0, 1.0});
    const Dynamics fine = Dynamics::paper_row({3, 1e8, 0.5, 0.0, 1.0});
    CHECK(plan_step(fine, Scheme::exact, 1e-6).scheme == Scheme::exact);
    CHECK_THROWS_WITH_AS(plan_step(stiff, Scheme::exact, 1e-6),
                         doctest::Contains("run.scheme: exact takes contacts of up to"),
                         std::invalid_argument);
    CHECK(plan_step(fine, Scheme::automatic, 1e-6).scheme == Scheme::exact);
    CHECK(plan_step(stiff, Scheme::automatic, 1e-6).scheme == Scheme::rk4);
    CHECK_THROWS_WITH_AS(require_orbit_size(stiff, Scheme::exact),
                         doctest::Contains("scheme: exact takes contacts"), std::invalid_argument);
}

TEST_CASE("the exact scheme is refused for an undamped row forced at a natural frequency") {
    // eps = 0, f_r = 1: u1 = -pi t sin(2 pi t) without contact, which rk4 follows to 2e-4;
    // exact's closed form, whose particular solution does not exist there, was off by 266.
    const Dynamics resonant = Dynamics::paper_row({5, 60, 0.0, 1000.0, 1.0});
    CHECK_THROWS_WITH_AS(plan_step(resonant, Scheme::exact, 1e-6),
                         doctest::Contains("exact cannot take an undamped row forced at a natural"),
                         std::invalid_argument);
    CHECK(plan_step(resonant, Scheme::automatic, 1e-6).scheme == Scheme::rk4);
    RunOptions o;
    o.periods = 40;
    o.transient_periods = 0;
    o.stop_at_steady_state = false;
    o.estimate_error = false;
    o.multistability_check = false;
    o.tolerance = 1e-8;
    double largest = 0.0, worst = 0.0;
    SimulationHooks hooks;
    hooks.trajectory = [&](double t, const double* y) {
        const double expected = -std::numbers::pi * t * std::sin(2.0 * std::numbers::pi * t);
        largest = std::max(largest, std::abs(expected));
        worst = std::max(worst, std::abs(y[0] - expected));
    };
    simulate(resonant, o, {}, hooks);
    CHECK(largest > 100.0);
    CHECK(worst < 1e-4 * largest);
    // Off the contact-free configuration: one wall closed on a single body (fc = 3) has
    // f = sqrt(1 + fc) = 2; met during the run, it is refused there.
    const Dynamics walled = Dynamics::paper_row({1, 3, 0.0, 0.01, 2.0});
    RunOptions exact;
    exact.scheme = Scheme::exact;
    exact.periods = 20;
    CHECK_THROWS_WITH_AS(
        simulate(walled, exact),
        doctest::Contains("natural frequency of one of its contact configurations"),
        std::invalid_argument);
}

TEST_CASE("the exact scheme is refused above max_exact_bodies, naming run.scheme and Nm") {
    // A long row visits new contact states at almost every step, each an O(Nm^3) set-up that
    // no cancel interrupts (Nm = 2000: hours, deaf to SIGINT).
    const Dynamics largest = Dynamics::paper_row({max_exact_bodies, 100, 0.5, 0.5, 1.0});
    CHECK(plan_step(largest, Scheme::exact, 1e-6).scheme == Scheme::exact);
    const Dynamics longer = Dynamics::paper_row({max_exact_bodies + 1, 100, 0.5, 0.5, 1.0});
    CHECK_THROWS_WITH_AS(plan_step(longer, Scheme::exact, 1e-6),
                         doctest::Contains("run.scheme: exact takes rows of up to 64 bodies"),
                         std::invalid_argument);
    // At the limit it still runs: one step of the largest row it takes.
    const StepPlan plan = plan_step(largest, Scheme::exact, 1e-6);
    auto stepper = make_stepper(plan, largest);
    std::vector<double> y(2 * max_exact_bodies, 0.0);
    stepper->step(0.0, plan.step, y);
    CHECK(std::isfinite(y[0]));
    CHECK(y[max_exact_bodies] != 0.0); // the forcing has moved the first body
}

TEST_CASE("the planned step fits the forcing period and tightens with the tolerance") {
    const ReducedParameters p{3, 60, 0.5, 0.1, 2.7};
    const Dynamics dyn = Dynamics::paper_row(p);
    const StepPlan loose = plan_step(dyn, Scheme::rk4, 1e-3);
    const StepPlan tight = plan_step(dyn, Scheme::rk4, 1e-8);
    CHECK(loose.step * loose.steps_per_period == doctest::Approx(dyn.period()).epsilon(1e-14));
    CHECK(tight.step < loose.step);
    CHECK(tight.step * dyn.max_angular_frequency() < traits(Scheme::rk4).stability_limit);
    CHECK(plan_step(dyn, Scheme::automatic, 1e-4).scheme == Scheme::rk4);
    CHECK_THROWS_AS(parse_scheme("euler"), std::invalid_argument);
}

namespace {
SimulationResult run_with(const ReducedParameters& p, Scheme s, double tolerance, long periods) {
    const Dynamics dyn = Dynamics::paper_row(p);
    RunOptions o;
    o.scheme = s;
    o.tolerance = tolerance;
    o.periods = periods;
    // The start is the hardest part for the schemes (impacts from rest): it is counted.
    o.transient_periods = 0;
    o.estimate_error = false;
    return simulate(dyn, o);
}
} // namespace

TEST_CASE("exact agrees with rk8pd at tolerance 1e-10 to better than 1e-8 in F_m") {
    const ReducedParameters scenes[] = {{5, 100, 0.5, 0.5, 1.0},    // smooth
                                        {20, 2000, 0.5, 0.24, 1.0}, // stiff
                                        {3, 500, 0.05, 1.0, 1.0}};  // low damping
    for (const auto& p : scenes) {
        const SimulationResult exact = run_with(p, Scheme::exact, 1e-10, 300);
        const SimulationResult rk8pd = run_with(p, Scheme::rk8pd, 1e-10, 300);
        CAPTURE(p.Nm);
        REQUIRE(exact.steady_state_period.has_value());
        CHECK(std::abs(exact.F_m - rk8pd.F_m) < 1e-8 * exact.F_m);
        for (std::size_t i = 0; i < exact.final_state.size(); ++i)
            CHECK(exact.final_state[i] ==
                  doctest::Approx(rk8pd.final_state[i]).epsilon(1e-8).scale(1));
    }
}

TEST_CASE("critical damping (eps = 1): exact agrees with rk8pd, as just off it") {
    // A contact-free mode of eps = 1 has one repeated eigenvalue and one eigenvector: the
    // eigendecomposition gave F_m 0.393103 against rk8pd's 0.391612 here, and final states 9e-3
    // apart; at eps = 1 + 1e-9 the two agreed to 3e-13.
    for (const double eps : {1.0, 1.0 + 1e-9}) {
        const ReducedParameters p{2, 100, eps, 0.3, 1.0};
        const SimulationResult exact = run_with(p, Scheme::exact, 1e-10, 100);
        const SimulationResult rk8pd = run_with(p, Scheme::rk8pd, 1e-11, 100);
        CAPTURE(eps);
        CHECK(std::abs(exact.F_m - rk8pd.F_m) < 1e-8 * rk8pd.F_m);
        for (std::size_t i = 0; i < exact.final_state.size(); ++i)
            CHECK(exact.final_state[i] ==
                  doctest::Approx(rk8pd.final_state[i]).epsilon(1e-6).scale(1));
    }
    // Five bodies (Fig 13's row at eps = 1): the orbit is period 2, as just off it.
    RunOptions o;
    o.scheme = Scheme::exact;
    const SimulationResult at = simulate(Dynamics::paper_row({5, 60, 1.0, 0.06, 3.0}), o);
    const SimulationResult off = simulate(Dynamics::paper_row({5, 60, 0.9999, 0.06, 3.0}), o);
    REQUIRE(at.steady_state_period.has_value());
    REQUIRE(off.steady_state_period.has_value());
    CHECK(*off.steady_state_period == 2);
    CHECK(*at.steady_state_period == 2);
    CHECK(at.F_m == doctest::Approx(off.F_m).epsilon(1e-3));
}

TEST_CASE("extreme cases: finite, and two schemes agree to the requested tolerance") {
    struct Case {
        const char* name;
        ReducedParameters p;
        long periods;
        Scheme a, b;
        double tolerance;
    };
    const Case cases[] = {
        {"fc = 1e6 (stiff contact)", {3, 1e6, 0.5, 0.3, 1.0}, 6, Scheme::rk4, Scheme::exact, 1e-6},
        {"eps = 1e-3 (nearly undamped; chaotic, so 3 periods)",
         {3, 100, 1e-3, 0.5, 1.0},
         3,
         Scheme::rk4,
         Scheme::exact,
         1e-6},
        {"eps = 2 (overdamped)", {3, 100, 2.0, 0.05, 1.0}, 20, Scheme::rk4, Scheme::exact, 1e-6},
        {"e_r = 0 (touching at rest)",
         {4, 100, 0.5, 0.0, 1.0},
         20,
         Scheme::rk4,
         Scheme::exact,
         1e-6},
        {"Nm = 1", {1, 100, 0.5, 0.5, 1.0}, 20, Scheme::rk4, Scheme::exact, 1e-6},
        {"Nm = 1000", {1000, 100, 0.5, 0.5, 1.0}, 3, Scheme::rk4, Scheme::rkf45, 1e-5},
        {"f_r = 0.01 (quasi-static)",
         {3, 100, 0.5, 0.5, 0.01},
         2,
         Scheme::rk4,
         Scheme::exact,
         1e-6},
        {"f_r = 20 (far above resonance)",
         {3, 100, 0.5, 0.001, 20.0},
         40,
         Scheme::rk4,
         Scheme::exact,
         1e-6},
    };
    for (const Case& c : cases) {
        const std::string name = c.name;
        CAPTURE(name);
        const SimulationResult a = run_with(c.p, c.a, c.tolerance, c.periods);
        const SimulationResult b = run_with(c.p, c.b, c.tolerance, c.periods);
        REQUIRE(a.status != RunStatus::non_finite);
        REQUIRE(b.status != RunStatus::non_finite);
        CHECK(std::isfinite(a.F_m));
        CHECK(a.contact);
        MESSAGE(name << ": " << a.F_m << " vs " << b.F_m << " rel "
                     << std::abs(a.F_m - b.F_m) / b.F_m << " periods " << a.periods_simulated << "/"
                     << b.periods_simulated);
        CHECK(std::abs(a.F_m - b.F_m) <= c.tolerance * b.F_m);
    }
}
