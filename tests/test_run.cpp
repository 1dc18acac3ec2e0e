// The time loop (run.hpp): period boundaries, switch splitting, the steady-state stop and
// cancellation, checked against the equations of motion and counted events.
#include "gapchain/observers.hpp"
#include "gapchain/run.hpp"
#include "gapchain/simulation.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <vector>

using namespace gapchain;

namespace {

/// Records what the loop hands to observers.
class LoopLog final : public Observer {
public:
    void on_step(const StepView& s) override {
        steps.push_back({s.t0, s.t1});
        if (s.recording) ++recorded;
    }
    bool on_period(long n, double t, const double*) override {
        boundaries.push_back({static_cast<double>(n), t});
        return false;
    }
    std::vector<std::pair<double, double>> steps;
    std::vector<std::pair<double, double>> boundaries;
    long recorded = 0;
};

Dynamics row(double e_r, double f_r) {
    return Dynamics::paper_row({2, 100.0, 0.5, e_r, f_r});
}

RunOptions rk4_options(long periods, long transient) {
    RunOptions o;
    o.periods = periods;
    o.transient_periods = transient;
    o.scheme = Scheme::rk4;
    o.step = 1e-3;
    return o;
}

} // namespace

TEST_CASE("run: period boundaries fall on exact multiples of the forcing period") {
    const Dynamics dyn = row(10.0, 1.25); // clearance too wide to close: no switches
    PlannedRun planned(dyn, rk4_options(7, 2));
    LoopLog log;
    Observer* observers[] = {&log};
    const RunOutcome out = planned.run(observers);
    CHECK(out.status == RunStatus::completed);
    CHECK(out.periods_done == 7);
    REQUIRE(log.boundaries.size() == 8);
    for (std::size_t n = 0; n < log.boundaries.size(); ++n)
        CHECK(log.boundaries[n].second == doctest::Approx(n / 1.25).epsilon(1e-15));
    // Without contact no step is split, and the transient steps are not recorded.
    const long per_period = planned.plan().steps_per_period;
    CHECK(static_cast<long>(log.steps.size()) == 7 * per_period);
    CHECK(log.recorded == 5 * per_period);
}

namespace {

/// Largest |gap| at the step end nearer a contact switch, over the steps that switch.
double largest_gap_at_switches(const Dynamics& dyn, bool split) {
    RunOptions o = rk4_options(3, 0);
    StepPlan plan = plan_run(dyn, o);
    plan.split_at_switches = split;
    PlannedRun planned(dyn, o, plan, {});
    struct GapWatch final : Observer {
        const Dynamics& dyn;
        double largest = 0.0;
        long switches = 0;
        explicit GapWatch(const Dynamics& d) : dyn(d) {}
        void on_step(const StepView& s) override {
            for (int j = 0; j < dyn.gaps(); ++j) {
                const double g0 = dyn.gap(j, s.y0), g1 = dyn.gap(j, s.y1);
                if ((g0 > 0.0) == (g1 > 0.0)) continue;
                largest = std::max(largest, std::min(std::abs(g0), std::abs(g1)));
                ++switches;
            }
        }
    } watch(dyn);
    Observer* observers[] = {&watch};
    planned.run(observers);
    REQUIRE(watch.switches >= 2); // the row does hit
    return watch.largest;
}

} // namespace

TEST_CASE("run: a step that straddles a contact switch ends on it") {
    // From rest the ground pushes the row into the walls at e_r = 0.05: contacts close and
    // open. With splitting every switch is a step end, located on the quintic interpolant of
    // the gap (the gap there is ~1e-8, against ~1e-4 per step of h = 1e-3 without splitting).
    const Dynamics dyn = row(0.05, 1.0);
    CHECK(largest_gap_at_switches(dyn, true) < 1e-6);
    CHECK(largest_gap_at_switches(dyn, false) > 1e-5);
}

TEST_CASE("run: a contact that closes and opens again inside one step is split there (a "
          "graze)") {
    // Fig 4's row at fc 1000, e_r 0.125, f_r 0.1: bodies reach the walls slowly while the
    // ground pulls them back, and such contacts last less than the exact propagator's output
    // interval (a quarter of the shortest contact period). Found only where a gap changed sign
    // between step ends, 3 of 36 impacts per period at the walls were missed, and F_m was
    // 0.121834 against 0.119333; a step that starts on a switch and comes back across the
    // surface was missed too.
    const Dynamics dyn = Dynamics::paper_row({5, 1000.0, 0.5, 0.125, 0.1});
    RunOptions o;
    o.periods = 300;
    o.estimate_error = false;
    o.multistability_check = false;
    o.scheme = Scheme::rk8pd;
    o.tolerance = 1e-10;
    const SimulationResult reference = simulate(dyn, o);
    o.scheme = Scheme::exact;
    o.tolerance = 1e-8;
    const SimulationResult exact = simulate(dyn, o);
    MESSAGE("exact " << exact.F_m << ", rk8pd " << reference.F_m);
    REQUIRE(reference.steady_state_period == 1);
    CHECK(exact.steady_state_period == 1);
    CHECK(exact.F_m == doctest::Approx(reference.F_m).epsilon(1e-8));
}

TEST_CASE("run: of two switches inside one exact step, the earlier ends it, wherever the "
          "interpolant puts them") {
    // Fig 13's row at f_r = 2.4088, from a state on its unstable period-1 orbit (rk8pd's): in
    // one step of 0.022, contact 2 closes 1.9e-4 before the left wall opens. The interpolant,
    // which spans the wall's kink, put the closing after the opening; the step ended at the
    // opening, contact 2 closed late, and one period of the exact scheme ended 1.4e-5 off
    // rk8pd and rkf45 (which agree to 1e-11).
    const Dynamics dyn = Dynamics::paper_row({5, 60.0, 0.5, 0.06, 2.4088});
    const std::vector<double> start{
        0.25173929192078737,    0.24529689930592485, 0.21758192004651988, 0.0507164321878801,
        -0.0025058064125087253, -1.841239893951036,  -1.7495052343264015, -4.740461951186742,
        -3.7641878452897317,    -1.284527488834453};
    RunOptions o;
    o.periods = 1;
    o.transient_periods = 0;
    o.stop_at_steady_state = false;
    o.estimate_error = false;
    o.multistability_check = false;
    o.tolerance = 1e-12;
    o.scheme = Scheme::rk8pd;
    const std::vector<double> reference = simulate(dyn, o, start).final_state;
    o.scheme = Scheme::exact;
    const std::vector<double> exact = simulate(dyn, o, start).final_state;
    double largest = 0.0;
    for (std::size_t i = 0; i < exact.size(); ++i)
        largest = std::max(largest, std::abs(exact[i] - reference[i]));
    MESSAGE("largest state difference exact - rk8pd after one period: " << largest);
    CHECK(largest < 1e-10);
}

TEST_CASE("run: the steady-state stop ends the run early, at a period boundary") {
    const Dynamics dyn = row(10.0, 1.0); // linear, damped: periodic after the transient
    PlannedRun planned(dyn, rk4_options(2000, 0));
    SteadyStateDetector steady(dyn.dimension(), 4, 1e-10, 0);
    Observer* observers[] = {&steady};
    const RunOutcome out = planned.run(observers);
    CHECK(out.status == RunStatus::steady_state);
    CHECK(out.periods_done < 2000);
    CHECK(steady.period() == 1);
    CHECK(out.t_end == doctest::Approx(static_cast<double>(out.periods_done)).epsilon(1e-15));
}

TEST_CASE("run: a progress callback that answers false cancels at the next report") {
    const Dynamics dyn = row(10.0, 1.0);
    PlannedRun planned(dyn, rk4_options(1000, 0));
    int calls = 0;
    const RunOutcome out = planned.run({}, [&](double) { return ++calls < 3; });
    CHECK(out.status == RunStatus::cancelled);
    CHECK(calls == 3);
    CHECK(out.periods_done == 3 * (1000 / 200)); // reports every periods / 200 periods
}

TEST_CASE("run: a long row is asked inside its first period, and a false answer stops it there") {
    // 20,000 bodies: asked every 13 pieces (2^18 / Nm), so well before the period's end.
    const ReducedParameters p{20000, 100, 0.5, 0.06, 1.0};
    const Dynamics dyn = Dynamics::paper_row(p);
    RunOptions o;
    o.periods = 1000;
    o.transient_periods = 0;
    PlannedRun planned(dyn, o);
    std::vector<double> fractions;
    const RunOutcome out = planned.run({}, [&](double f) {
        fractions.push_back(f);
        return false;
    });
    CHECK(out.status == RunStatus::cancelled);
    CHECK(out.periods_done == 0);
    REQUIRE(fractions.size() == 1);
    CHECK(fractions[0] > 0.0);
    CHECK(fractions[0] < 1.0 / o.periods);
}

TEST_CASE("PlannedRun: bad options and states are refused before running") {
    const Dynamics dyn = row(0.5, 1.0);
    RunOptions o = rk4_options(10, 10);
    CHECK_THROWS_AS(PlannedRun(dyn, o), std::invalid_argument);
    o = rk4_options(10, 0);
    CHECK_THROWS_AS(PlannedRun(dyn, o, std::vector<double>(3, 0.0)), std::invalid_argument);
}

TEST_CASE("default transient: the slowest free decay of the start, also beyond critical damping") {
    // The contact-free body's characteristic roots: lambda^2 + 4 pi eps lambda + 4 pi^2 = 0.
    // Below critical damping both decay at 2 pi eps; beyond it the slow root, 2 pi (eps -
    // sqrt(eps^2 - 1)), sets how long the start takes to fade (MODEL.md §2's 2 pi eps is the
    // underdamped case).
    const double pi = std::numbers::pi;
    for (double eps : {0.3, 0.9, 1.5, 5.0, 100.0})
        for (double f_r : {0.5, 2.0}) {
            const Dynamics dyn = Dynamics::paper_row({3, 100, eps, 2.0, f_r});
            RunOptions o;
            o.periods = 100000;
            const double rate = eps < 1 ? 2 * pi * eps : 2 * pi * (eps - std::sqrt(eps * eps - 1));
            const double decay_periods = f_r * std::log(1.0 / o.tolerance) / rate;
            CAPTURE(eps);
            CAPTURE(f_r);
            const long n_t = default_transient_periods(dyn, o);
            // The smallest whole number of periods after which exp(-rate t) <= tolerance.
            CHECK(n_t == std::max(1L, static_cast<long>(std::ceil(decay_periods - 1e-9))));
        }
}

TEST_CASE("run.max_work counts the exact propagator's set-up of contact configurations") {
    // Nm = 46 on exact, 5 periods: counted as 30,820 body-steps (Nm x steps), it was accepted
    // under run.max_work = 40,000 and ran 7 s (7e7 body-steps at 1e7 a second), setting up a
    // (2 Nm)^3 eigendecomposition for each contact configuration met.
    const Dynamics long_row = Dynamics::paper_row({46, 559, 0.1, 0.22, 1.0});
    RunOptions o;
    o.periods = 5;
    o.scheme = Scheme::exact;
    o.max_work = 40'000;
    CHECK_THROWS_WITH_AS(require_affordable(long_row, o),
                         doctest::Contains("a new contact configuration"), std::invalid_argument);
    const StepPlan plan = plan_run(long_row, o);
    const double n = long_row.dimension();
    CHECK(run_work(long_row, plan, 5) >= 5 * 2 * 47 * 0.5 * n * n * n);
    // A short row has at most 2^(Nm + 1) configurations, which its cache keeps: a long periodic
    // run on it is not charged for a set-up each period.
    const Dynamics short_row = Dynamics::paper_row({5, 60, 0.5, 0.06, 3.0});
    const StepPlan short_plan = plan_step(short_row, Scheme::exact, 1e-4);
    const double all_configurations = 64 * 0.5 * 1000.0;
    CHECK(run_work(short_row, short_plan, 1e6) - run_work(short_row, short_plan, 1e5) ==
          doctest::Approx(run_work(short_row, short_plan, 9e5) - all_configurations));
    // affordable_periods() is run_work()'s inverse: the largest whole number of periods within.
    for (double budget : {1e4, 3e4, 1e6, 3e10}) {
        const double p = affordable_periods(short_row, short_plan, budget);
        CHECK(run_work(short_row, short_plan, p) <= budget);
        CHECK(run_work(short_row, short_plan, p + 1) > budget);
    }
    // The other schemes: Nm x steps per period, as before.
    const StepPlan rk4 = plan_step(long_row, Scheme::rk4, 1e-4);
    CHECK(run_work(long_row, rk4, 7) == 46.0 * rk4.steps_per_period * 7);
}

TEST_CASE("run.max_work counts the matrix exponentials of a critically damped row on exact") {
    // Fig 13's row at f_r = 3 on exact, 300 periods: eps = 1 ran 0.107 s where eps = 0.999 ran
    // 0.0085 s (12.5x; Nm = 40: 150x), but was counted the same, 70,400 body-steps (7 ms).
    const auto work = [](double eps, int Nm) {
        const Dynamics row = Dynamics::paper_row({Nm, 60, eps, 0.06, 3.0});
        return run_work(row, plan_step(row, Scheme::exact, 1e-4), 300);
    };
    // The measured times at 1e7 body-steps a second: the whole run, and what eps = 1 adds.
    CHECK(work(1.0, 5) >= 0.107 * 1e7);
    CHECK(work(1.0, 5) - work(0.999, 5) >= (0.107 - 0.0085) * 1e7);
    CHECK(work(1.0, 40) >= 56.0 * 1e7);
    // Only critical damping: 1e-8 below it the eigendecompositions hold (0.08 s for 2000
    // periods, as at 0.9999).
    CHECK(work(1.0 - 1e-8, 5) == work(0.999, 5));
    // A row of arrays: one critically damped body is enough.
    RunOptions o;
    o.scheme = Scheme::exact;
    Chain chain = Chain::homogeneous({3, 60, 0.5, 0.06, 3.0});
    const Dynamics damped_below(chain, GroundMotion::harmonic(3.0));
    chain.damping[1] = 2.0 * std::sqrt(chain.spring[1]);
    const Dynamics one_critical(chain, GroundMotion::harmonic(3.0));
    CHECK(run_work(one_critical, plan_run(one_critical, o), 300) >
          5 * run_work(damped_below, plan_run(damped_below, o), 300));
}

TEST_CASE("run.max_work counts the exact propagator's contact switches on a 16-step plan") {
    // At f_r >= 1 the exact plan takes 16 steps a period, each spanning switches: Fig 13's row
    // ran 0.13 s (Nm 2) and 0.35 s (Nm 5) for 3000 periods at f_r = 1 and was counted 0.026 s and
    // 0.11 s. The count must be at least the measured time at 1e7 body-steps a second.
    const std::pair<int, double> measured[] = {{2, 0.13}, {5, 0.35}};
    for (const auto& [Nm, seconds] : measured) {
        const Dynamics row = Dynamics::paper_row({Nm, 60, 0.5, 0.06, 1.0});
        CHECK(run_work(row, plan_step(row, Scheme::exact, 1e-4), 3000) >= seconds * 1e7);
    }
}
