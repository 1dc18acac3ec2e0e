#include "gapchain/design_value.hpp"

#include "gapchain/classify.hpp"
#include "gapchain/report.hpp"
#include "gapchain/scene.hpp"
#include "gapchain/simulation.hpp"

#include "attractor_searches.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

using namespace gapchain;
using test::short_runs;

TEST_CASE("design value: a run from rest that reaches the weaker of Fig 13's attractors at "
          "f_r = 3.2 is flagged, with the torus's F_m as the design value") {
    const ReducedParameters p{5, 60, 0.5, 0.06, 3.2};
    AttractorOptions o = short_runs(100, 1);
    o.box = 1.0;
    o.run.periods = 600;
    o.run.transient_periods = 300;
    const SimulationResult from_rest = simulate(Dynamics::paper_row(p), o.run);
    // The torus, reached from the start by a plain run: an independent witness.
    const SimulationResult torus =
        simulate(Dynamics::paper_row(p), o.run, {0.5, -0.5, 0.5, -0.5, 0.5, 0, 0, 0, 0, 0});
    REQUIRE(torus.F_m > from_rest.F_m + 3.0 * (from_rest.F_m_error + torus.F_m_error));
    const DesignValue d = design_value(p, o, from_rest);
    CHECK(d.start_below);
    CHECK_FALSE(d.run_above);
    CHECK_FALSE(d.from_run);
    CHECK(d.F_m_max == d.search.F_m_max);
    CHECK(d.F_m_max == doctest::Approx(torus.F_m).epsilon(1e-3));
    CHECK(d.F_m_max_error == d.search.F_m_max_error);
    // The torus's own run, set against the same search, is the design value within errors.
    const DesignValue on_torus = design_value(p, o, torus);
    CHECK_FALSE(on_torus.start_below);
    CHECK_FALSE(on_torus.run_above);
    // The JSON of gapchain-sim says multistable, though the run alone (no twin flag) did not.
    Scene scene = parse_scene("{}", {}, "<test>");
    scene.reduced = p;
    scene.run = o.run;
    REQUIRE_FALSE(from_rest.multistable);
    const std::string json = to_json(from_rest, scene, d, o);
    CHECK(json.find("\"multistable\": true") != std::string::npos);
    CHECK(json.find("\"start_below\": true") != std::string::npos);
}

TEST_CASE("design value: a run whose F_m is above every attractor (issue 19's Nm = 2 row, its "
          "chaotic transient) is flagged run_above; a contact-free row is plain") {
    const ReducedParameters nm2{2, 200, 0.1, 0.351, 0.626};
    AttractorOptions o = short_runs(40, 3);
    o.box = 1.0;
    o.run.periods = 1000;
    o.run.accuracy_mode = AccuracyMode::strict;
    // The run's own checks off: it still continues its orbit for a cycle (F_m_orbit is a
    // result) and says that its maximum came before it, its bar covering the gap. Without that
    // (a result as a run from before its orbit check gives it), nothing but the search says
    // that its F_m is a transient's.
    RunOptions unchecked = o.run;
    unchecked.estimate_error = false;
    unchecked.multistability_check = false;
    const SimulationResult own_check = simulate(Dynamics::paper_row(nm2), unchecked);
    REQUIRE(own_check.F_m_orbit.has_value());
    CHECK(own_check.maximum_in_transient);
    CHECK(own_check.F_m_error >= own_check.F_m - *own_check.F_m_orbit);
    CHECK_FALSE(design_value(nm2, o, own_check).run_above);
    SimulationResult from_rest = own_check;
    from_rest.F_m_orbit.reset();
    from_rest.maximum_in_transient = false;
    from_rest.F_m_error = 0.0;
    from_rest.error_method = ErrorMethod::none;
    const DesignValue d = design_value(nm2, o, from_rest);
    REQUIRE(d.search.attractors.size() == 1);
    // The period-3 orbit (Newton; an independent closed-form implementation gives 1.070351).
    CHECK(d.search.F_m_max == doctest::Approx(1.070351).epsilon(1e-5));
    CHECK(d.run_above);
    CHECK(d.from_run);
    CHECK(d.F_m_max == from_rest.F_m);
    CHECK(std::isnan(d.F_m_max_error)); // the run's error, not estimated: never written as 0
    CHECK_FALSE(d.start_below);
    CHECK(multistable(from_rest, d));
    // A run that did not answer (stopped) is not compared: the search's value stands alone.
    SimulationResult stopped = from_rest;
    stopped.status = RunStatus::cancelled;
    const DesignValue alone = design_value(nm2, o, stopped);
    CHECK_FALSE(alone.run_above);
    CHECK_FALSE(alone.from_run);
    CHECK(alone.F_m_max == alone.search.F_m_max);
    // With its checks the run's error bar covers the orbit's F_m already: not above beyond it.
    const SimulationResult checked = simulate(Dynamics::paper_row(nm2), o.run);
    CHECK(checked.multistable);
    CHECK_FALSE(design_value(nm2, o, checked).run_above);

    // No contact: one attractor, eq (20)'s response, the run's own F_m (0) is the design value.
    const ReducedParameters free_row{3, 100, 0.3, 50.0, 1.5};
    AttractorOptions f = short_runs(20, 4);
    const SimulationResult plain = simulate(Dynamics::paper_row(free_row), f.run);
    const DesignValue none = design_value(free_row, f, plain);
    CHECK(none.search.attractors.size() == 1);
    CHECK(none.F_m_max == 0.0);
    CHECK_FALSE(none.start_below);
    CHECK_FALSE(none.run_above);
}

TEST_CASE("design value: where no group settled, it is the larger of the run's F_m and the "
          "groups', and from_run says which") {
    // Too short to settle (60 periods): every group of 4 starts is still converging.
    const ReducedParameters p{3, 100, 0.5, 0.1, 1.0};
    AttractorOptions o = short_runs(4, 1);
    o.box = 1.0;
    o.run.periods = 60;
    const SimulationResult run = simulate(Dynamics::paper_row(p), o.run);
    const DesignValue d = design_value(p, o, run);
    REQUIRE(d.search.unsettled == static_cast<int>(d.search.attractors.size()));
    CHECK(d.F_m_max == std::max(run.F_m, d.search.F_m_max));
    CHECK(d.from_run == (run.F_m >= d.search.F_m_max));
    CHECK(d.F_m_max_error == (d.from_run ? run.F_m_error : d.search.F_m_max_error));
    // Nothing settled: no comparison with an attractor is made.
    CHECK_FALSE(d.start_below);
    CHECK_FALSE(d.run_above);
}

TEST_CASE("design value: a search stopped before any start ended and a run that did not answer "
          "give none, not 0") {
    // A reread (helper-86): the sweep took design.F_m_max, 0 +- 0, as the point's design value.
    const ReducedParameters p{3, 100, 0.5, 0.1, 1.0};
    const AttractorOptions o = short_runs(4, 1);
    const DesignValue stopped = design_value(p, o, RunAnswer{}, [](double) { return false; });
    CHECK(std::isnan(stopped.F_m_max));
    CHECK(std::isnan(stopped.F_m_max_error));
    // The run's answer stands alone where the search has nothing to set against it.
    RunAnswer answered;
    answered.answered = true;
    answered.F_m = 0.4;
    answered.F_m_error = 0.01;
    const DesignValue from_run = design_value(p, o, answered, [](double) { return false; });
    CHECK(std::isnan(from_run.F_m_max)); // cancelled: no verdict at all
}

TEST_CASE("a chaotic label read on a chaotic saddle's transient is told apart from a chaotic "
          "attractor (classify against the row's attractors)") {
    // Fig 13's row at f_r = 2.05: from rest classify reads chaos (lambda_max +1.6, F_m 1.148)
    // through its 400 periods; the row's one attractor is the period-3 orbit of F_m 1.15579
    // (an independent probe saw every one of 100 starts end on it, the previous case). At
    // f_r = 3.35 the chaos is an attractor (docs/attractors.md's line: label 3, chaotic from
    // 3.3 to 3.45) and the label stands.
    AttractorOptions o;
    o.samples = 8;
    o.run.periods = 400;
    o.run.transient_periods = 100;
    const ReducedParameters saddle{5, 60, 0.5, 0.06, 2.05};
    const Classification c = classify(saddle, ClassifyOptions{});
    REQUIRE(c.regime == Regime::chaotic);
    const DesignValue d = design_value(saddle, o, c);
    CHECK(label_in_search(c, d) == LabelInSearch::transient);
    CHECK(d.start_below);
    CHECK_FALSE(d.from_run);
    CHECK(d.F_m_max == doctest::Approx(1.15579).epsilon(1e-5));

    const ReducedParameters chaos{5, 60, 0.5, 0.06, 3.35};
    const Classification k = classify(chaos, ClassifyOptions{});
    REQUIRE(k.regime == Regime::chaotic);
    const DesignValue e = design_value(chaos, o, k);
    CHECK(label_in_search(k, e) == LabelInSearch::attractor);
    CHECK_FALSE(e.start_below);
    // A periodic label is never called a transient, whatever the search found.
    Classification periodic = c;
    periodic.regime = Regime::periodic;
    CHECK(label_in_search(periodic, d) == LabelInSearch::not_applicable);
    // Nor is a chaotic motion no start of the search reached (a reviewer's probe: a start on
    // f_r = 3.15's chaotic attractor of basin 0.067, which 8 starts missed, read "transient"
    // while the rule was "the search settled on orbits alone").
    Classification unreached = c;
    unreached.F_m = 0.8;
    CHECK(label_in_search(unreached, d) == LabelInSearch::not_reached);
}

TEST_CASE("label_in_search matches a non-periodic label to a group by F_m, not by label") {
    // Fig 13's row at f_r = 3.2 (a reviewer's probe): the label's motion was the search's
    // unsettled group (the slow approach to the period-15 orbit, F_m 0.2518) while an unrelated
    // torus (F_m 0.385) settled; "any settled non-periodic attractor" called the label an
    // attractor's.
    Classification c;
    c.regime = Regime::chaotic;
    c.F_m = 0.2535;
    c.F_m_error = 0.002;
    DesignValue d;
    Attractor torus;
    torus.regime = Regime::quasi_periodic;
    torus.F_m = 0.385;
    torus.F_m_error = 1e-4;
    Attractor approach;
    approach.regime = Regime::quasi_periodic;
    approach.settled = false;
    approach.F_m = 0.2518;
    approach.F_m_error = 0.001;
    d.search.attractors = {torus, approach};
    CHECK(label_in_search(c, d) == LabelInSearch::transient);
    // The same F_m on a settled group: the label is that attractor's.
    d.search.attractors[1].settled = true;
    CHECK(label_in_search(c, d) == LabelInSearch::attractor);
    // Beyond three error bars and 5 %: not that group.
    c.F_m = 0.30;
    CHECK(label_in_search(c, d) == LabelInSearch::not_reached);
    // An orbit of the same F_m is no match for a non-periodic motion.
    Attractor orbit;
    orbit.period = 3;
    orbit.F_m = 0.30;
    d.search.attractors = {orbit};
    CHECK(label_in_search(c, d) == LabelInSearch::not_reached);
}

TEST_CASE("label_in_search: two motions of one F_m are told apart by their section points") {
    // Matched by F_m alone, a chaotic saddle whose F_m a settled chaotic attractor shares would
    // read `attractor`. Where the classification kept its section states the clouds must
    // overlap as the search's own grouping tests them.
    const ReducedParameters row{1, 100, 0.5, 0.5, 1.0};
    const auto cloud = [](double u_center, double v_center, int n) {
        std::vector<std::vector<double>> points;
        for (int k = 0; k < n; ++k)
            points.push_back(
                {u_center + 0.01 * std::sin(1.3 * k), v_center + 0.01 * std::cos(0.7 * k)});
        return points;
    };
    Classification c;
    c.regime = Regime::chaotic;
    c.F_m = 0.5;
    c.F_m_error = 0.001;
    c.section_states = cloud(0.3, 0.0, 300);
    Attractor elsewhere;
    elsewhere.F_m = 0.5;
    elsewhere.F_m_error = 0.001;
    elsewhere.section = cloud(-0.3, 0.5, 200);
    DesignValue d;
    d.row = row;
    d.search.attractors = {elsewhere};
    CHECK(label_in_search(c, d) == LabelInSearch::not_reached);
    // The same cloud sampled again: that attractor.
    d.search.attractors[0].section = cloud(0.3, 0.0, 200);
    CHECK(label_in_search(c, d) == LabelInSearch::attractor);
    // Without section states (a classification that did not keep them), F_m alone decides.
    d.search.attractors[0].section = cloud(-0.3, 0.5, 200);
    c.section_states.clear();
    CHECK(label_in_search(c, d) == LabelInSearch::attractor);
}
