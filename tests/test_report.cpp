#include "gapchain/orbit.hpp"
#include "gapchain/poincare.hpp"
#include "gapchain/report.hpp"
#include "gapchain/scene.hpp"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

using namespace gapchain;

namespace {

/// Field k (0-based) of CSV line `line` (0: the header) of text.
std::string csv_field(const std::string& text, int line, int k) {
    std::istringstream lines(text);
    std::string row;
    for (int i = 0; i <= line; ++i)
        std::getline(lines, row);
    std::istringstream fields(row);
    std::string field;
    for (int i = 0; i <= k; ++i)
        std::getline(fields, field, ',');
    return field;
}

} // namespace

TEST_CASE("map_csv: an unknown lambda_max_error is an empty field, a known one its number") {
    RegimeMap map;
    map.e_r = {0.06};
    map.f_r = {2.0, 3.3};
    map.cells.resize(2);
    map.cells[0].regime = Regime::periodic;
    map.cells[0].lambda_max = -1.5;
    // A point that settled within 20 periods: too few blocks for a standard error.
    map.cells[0].lambda_max_error = std::numeric_limits<double>::infinity();
    map.cells[1].regime = Regime::chaotic;
    map.cells[1].lambda_max = 0.83;
    map.cells[1].lambda_max_error = 0.06;
    const std::string csv = map_csv(map);
    REQUIRE(csv_field(csv, 0, 7) == "lambda_max_error");
    CHECK(csv_field(csv, 1, 6) == "-1.5");
    CHECK(csv_field(csv, 1, 7).empty());
    CHECK(csv_field(csv, 2, 7) == "0.06");
    CHECK(csv.find("inf") == std::string::npos);
}

TEST_CASE("simulation JSON: multistable is null where the check did not run, never false") {
    const Scene scene = parse_scene(R"({"model": {"Nm": 2}})");
    SimulationResult r;
    r.multistability_checked = false;
    CHECK(to_json(r, scene).find("\"multistable\": null") != std::string::npos);
    r.multistability_checked = true;
    CHECK(to_json(r, scene).find("\"multistable\": false") != std::string::npos);
    r.multistable = true;
    CHECK(to_json(r, scene).find("\"multistable\": true") != std::string::npos);
}

TEST_CASE("Lyapunov and orbit JSON name the row that ran: its chain, where arrays give one") {
    // They wrote the five numbers alone: eps = 0.5 of a row damped by [0.1, 0.2, 0.3].
    const Scene arrays = parse_scene(R"({"model": {"Nm": 3, "damping": [0.1, 0.2, 0.3]}})");
    const Scene uniform = parse_scene(R"({"model": {"Nm": 3}})");
    LyapunovResult l;
    l.expected_sum = -7.5;
    CHECK(to_json(l, arrays).find("\"chain\"") != std::string::npos);
    CHECK(to_json(l, arrays).find("\"expected_sum\": -7.5") != std::string::npos);
    CHECK(to_json(l, uniform).find("\"chain\"") == std::string::npos);
    l.expected_sum = std::numeric_limits<double>::quiet_NaN();
    CHECK(to_json(l, uniform).find("expected_sum") == std::string::npos);
    PeriodicOrbit o;
    CHECK(to_json(o, arrays).find("\"chain\"") != std::string::npos);
    CHECK(to_json(o, uniform).find("\"chain\"") == std::string::npos);
}

TEST_CASE("attractor and bifurcation JSON name the scheme that ran") {
    // --set run.scheme=rk4 and =auto gave lambda_max 0.830 and 1.013 under the same run block.
    AttractorOptions o;
    o.run.scheme = Scheme::rk4;
    o.run.step = 0.001;
    const ReducedParameters p{2, 60, 0.5, 0.1, 3.0};
    const std::string a = to_json(
        AttractorSet{}, o, parse_scene(R"({"model": {"Nm": 2, "fc": 60, "eps": 0.5, "e_r": 0.1},
                        "excitation": {"f_r": 3}})"));
    CHECK(a.find("\"scheme\": \"rk4\"") != std::string::npos);
    CHECK(a.find("\"step\": 0.001") != std::string::npos);
    BifurcationOptions b;
    b.scheme = Scheme::exact;
    CHECK(to_json(BifurcationResult{}, b, p).find("\"scheme\": \"exact\"") != std::string::npos);
    // auto is written as what it resolves to (rk4 at the default tolerance), and as asked.
    b.scheme = Scheme::automatic;
    const std::string resolved = to_json(BifurcationResult{}, b, p);
    CHECK(resolved.find("\"scheme\": \"rk4\"") != std::string::npos);
    CHECK(resolved.find("\"scheme_requested\": \"auto\"") != std::string::npos);
}

TEST_CASE("Lyapunov and orbit JSON name the scheme, step and run keys that ran, no others") {
    // Lyapunov JSON listed estimate_error, multistability_check and accuracy_mode, which the
    // tool refuses as keys it does not read, and no scheme; the orbit JSON no scheme at all.
    const Scene scene = parse_scene(R"({"model": {"Nm": 2}})");
    LyapunovResult l;
    l.scheme = Scheme::exact;
    l.step = 0.01;
    const auto lj = nlohmann::json::parse(to_json(l, scene));
    CHECK(lj["scheme"] == "exact");
    CHECK(lj["step"] == 0.01);
    CHECK(lj["parameters"].contains("tolerance"));
    for (const char* unread : {"estimate_error", "multistability_check", "accuracy_mode"})
        CHECK_FALSE(lj["parameters"].contains(unread));
    PeriodicOrbit o;
    o.scheme = Scheme::rk8pd;
    o.integration_tolerance = 1e-11;
    const auto oj = nlohmann::json::parse(to_json(o, scene));
    CHECK(oj["scheme"] == "rk8pd");
    CHECK(oj["integration_tolerance"] == 1e-11);
}

TEST_CASE("simulation JSON of a recorded ground motion names the record file and the type") {
    // The JSON said "harmonic": false and a duration, not which record the row was shaken by.
    const std::string record = "test_report_record.csv";
    std::ofstream(record) << "0,0\n0.01,1\n0.02,-1\n0.03,0\n";
    const Scene scene = parse_scene(R"({"units": "physical", "model": {"Nm": 2, "M": 100,
        "K": 1e5, "C": 500, "Kc": 5e7, "e": 0.003}, "excitation": {"type": "record", "file": ")" +
                                    record + R"("}})");
    std::remove(record.c_str());
    const auto j = nlohmann::json::parse(to_json(SimulationResult{}, scene));
    CHECK(j["excitation"]["type"] == "record");
    CHECK(j["excitation"]["record_file"] == record);
    const auto kanai_tajimi = nlohmann::json::parse(
        to_json(SimulationResult{}, parse_scene(R"({"units": "physical", "excitation": {"type":
        "kanai_tajimi", "duration": 1}})")));
    CHECK(kanai_tajimi["excitation"]["type"] == "kanai_tajimi");
    CHECK_FALSE(kanai_tajimi["excitation"].contains("record_file"));
    // No forcing frequency: f_r is null, not the reduced 1 (a reviewer's probe, helper-74).
    CHECK(j["parameters"]["f_r"].is_null());
    CHECK(kanai_tajimi["parameters"]["f_r"].is_null());
    const auto harmonic = nlohmann::json::parse(to_json(SimulationResult{}, parse_scene("{}")));
    CHECK(harmonic["parameters"]["f_r"].is_number());
}

TEST_CASE(
    "simulation JSON: each body's left and right maxima carry their errors, null if unknown") {
    const Scene scene = parse_scene(R"({"model": {"Nm": 2}})");
    SimulationResult r;
    r.per_body = {{0.5, 0.7, 1.0, 2.0}, {0.7, 0.2, 2.0, 3.0}};
    const auto body = [&](int i) {
        return nlohmann::json::parse(to_json(r, scene))["per_body"][i];
    };
    // Not estimated: unknown, never 0.
    CHECK(body(0)["left_error"].is_null());
    CHECK(body(1)["right_error"].is_null());
    r.per_body[0].left_error = 1e-4;
    r.per_body[1].right_error = 3e-4;
    CHECK(body(0)["left_error"] == 1e-4);
    CHECK(body(1)["right_error"] == 3e-4);
}

TEST_CASE("a physical scene's attractors and orbit are also given in newtons") {
    // M a0 sqrt(Kc / K) per reduced unit (MODEL.md section 3): 100 kg x 5 m/s^2 x sqrt(50).
    const Scene scene = parse_scene(R"({"units": "physical", "model": {"Nm": 2, "M": 100,
        "K": 1e5, "C": 500, "Kc": 5e6, "e": 0.002}, "excitation": {"a0": 5, "f": 4}})");
    const double newtons = 100 * 5 * std::sqrt(50.0);
    AttractorSet set;
    set.F_m_max = 0.7;
    set.F_m_max_error = 0.01;
    set.F_m_max_id = 0;
    set.attractors.resize(1);
    set.attractors[0].F_m = 0.7;
    const auto a = nlohmann::json::parse(to_json(set, AttractorOptions{}, scene));
    CHECK(a.at("F_m_max_newton").get<double>() == doctest::Approx(0.7 * newtons));
    CHECK(a.at("F_m_max_error_newton").get<double>() == doctest::Approx(0.01 * newtons));
    CHECK(a.at("attractors")[0].at("F_m_newton").get<double>() == doctest::Approx(0.7 * newtons));
    // No attractor, no design value: it read 0 +- 0 (helper-85).
    const auto none = nlohmann::json::parse(to_json(AttractorSet{}, AttractorOptions{}, scene));
    CHECK(none.at("F_m_max").is_null());
    CHECK(none.at("F_m_max_error").is_null());
    CHECK(none.at("F_m_max_newton").is_null());
    PeriodicOrbit orbit;
    orbit.F_m = 0.5;
    orbit.F_m_error = 1e-4;
    const auto j = nlohmann::json::parse(to_json(orbit, scene));
    CHECK(j.at("F_m_newton").get<double>() == doctest::Approx(0.5 * newtons));
    CHECK(j.at("F_m_error_newton").get<double>() == doctest::Approx(1e-4 * newtons));
    // A run set against the attractors (gapchain-sim --attractors): the design value's error in
    // newtons too (it was missing there, a reviewer's probe found).
    DesignValue d;
    d.search = set;
    d.F_m_max = 0.7;
    d.F_m_max_error = 0.01;
    const auto s = nlohmann::json::parse(
        to_json(SimulationResult{}, scene, d, AttractorOptions{}))["design_value"];
    CHECK(s.at("F_m_max_newton").get<double>() == doctest::Approx(0.7 * newtons));
    CHECK(s.at("F_m_max_error_newton").get<double>() == doctest::Approx(0.01 * newtons));
    // A reduced scene has none.
    const Scene reduced = parse_scene(R"({"model": {"Nm": 2}})");
    CHECK_FALSE(nlohmann::json::parse(to_json(set, AttractorOptions{}, reduced))
                    .contains("F_m_max_newton"));
}

TEST_CASE("attractors.json says how many section points a run that does not settle kept") {
    // One a recorded period: --section-points 100000 over 50 recorded periods keeps 50.
    const Scene scene =
        parse_scene(R"({"model": {"Nm": 2}, "run": {"periods": 100, "transient_periods": 50}})");
    AttractorOptions o;
    o.run = scene.run;
    o.section_points = 100000;
    const auto j = nlohmann::json::parse(to_json(AttractorSet{}, o, scene));
    CHECK(j.at("section_points") == 100000);
    CHECK(j.at("section_points_kept") == 50);
    o.section_points = 20;
    CHECK(nlohmann::json::parse(to_json(AttractorSet{}, o, scene)).at("section_points_kept") == 20);
}

TEST_CASE("continuation JSON: the largest F_m error of those estimated, the others counted") {
    // An interrupted continuation wrote branch.csv alone: nothing said it had been cut short.
    const Scene scene = parse_scene(R"({"model": {"Nm": 2, "fc": 60}})");
    ContinuationResult r;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (const double error : {1e-9, 3e-7, nan}) {
        BranchPoint p;
        p.F_m_error = error;
        r.points.push_back(p);
    }
    SpecialPoint fold;
    fold.F_m_error = 2e-6;
    r.special.push_back(fold);
    r.branch_end = {"cancelled"};
    r.cancelled = true;
    r.wall_time_s = 1.5;
    ContinuationOptions o;
    o.from = 2.5;
    o.to = 3.0;
    const auto j = nlohmann::json::parse(to_json(r, o, scene));
    CHECK(j["cancelled"] == true);
    CHECK(j["orbits"] == 3);
    CHECK(j["special_points"] == 1);
    CHECK(j["branches"] == 1);
    CHECK(j["branch_end"][0] == "cancelled");
    CHECK(j["max_F_m_error"] == 2e-6);
    CHECK(j["F_m_errors_not_estimated"] == 1);
    CHECK(j["from"] == 2.5);
    CHECK(j["to"] == 3.0);
    CHECK(j["parameter"] == "f_r");
    CHECK(j["wall_time_s"] == 1.5);
    CHECK(j["base"]["fc"] == 60);
    const ForceErrorSummary summary = force_error_summary(r);
    CHECK(summary.orbits == 4);
    CHECK(summary.unestimated == 1);
    CHECK(summary.largest == 2e-6);
}

TEST_CASE("classification JSON against the attractors: multistable, label_in_search, the "
          "design value") {
    const Scene scene = parse_scene(R"({"model": {"Nm": 5, "fc": 60}})");
    Classification c;
    c.regime = Regime::chaotic;
    c.F_m = 1.148;
    DesignValue d;
    Attractor orbit;
    orbit.regime = Regime::periodic;
    orbit.period = 3;
    orbit.F_m = 1.15579;
    Attractor saddle;
    saddle.regime = Regime::chaotic;
    saddle.settled = false;
    saddle.F_m = 1.149;
    d.search.attractors = {orbit, saddle};
    d.search.F_m_max = orbit.F_m;
    d.search.F_m_max_id = 0;
    d.F_m_max = orbit.F_m;
    d.start_below = true;
    const auto j =
        nlohmann::json::parse(to_json(c, ClassifyOptions{}, scene, d, AttractorOptions{}));
    CHECK(j["regime"] == "chaotic");
    CHECK(j["multistable"] == true);
    CHECK(j["label_in_search"] == "transient");
    CHECK(j["design_value"]["F_m_max"] == 1.15579);
    CHECK(j["design_value"]["attractor"]["period"] == 3);
    // The same group settled: the label is an attractor's, and without start_below or a
    // start-dependent twin nothing says multistable.
    d.search.attractors[1].settled = true;
    d.start_below = false;
    const auto k =
        nlohmann::json::parse(to_json(c, ClassifyOptions{}, scene, d, AttractorOptions{}));
    CHECK(k["label_in_search"] == "attractor");
    CHECK(k["multistable"] == false);
    // Above every attractor found, on the attractor the search settled on: one chaos sampled
    // longer, not multistable.
    d.run_above = true;
    CHECK(nlohmann::json::parse(
              to_json(c, ClassifyOptions{}, scene, d, AttractorOptions{}))["multistable"] == false);
    d.search.attractors[1].settled = false;
    CHECK(nlohmann::json::parse(
              to_json(c, ClassifyOptions{}, scene, d, AttractorOptions{}))["multistable"] == true);
    d.search.attractors[1].settled = true;
    // A periodic label has no place among the non-periodic groups: null.
    c.regime = Regime::periodic;
    CHECK(nlohmann::json::parse(
              to_json(c, ClassifyOptions{}, scene, d, AttractorOptions{}))["label_in_search"]
              .is_null());
}

TEST_CASE("section JSON names the scheme and step the run took, beside the ones asked for") {
    // "auto" and a null step alone did not say which scheme ran (a reviewer's probe, helper-77).
    const Scene scene =
        parse_scene(R"({"model": {"Nm": 2}, "run": {"periods": 20, "transient_periods": 10}})");
    const Dynamics dyn = scene.dynamics();
    const StepPlan plan = plan_run(dyn, scene.run);
    SectionSpec spec;
    const RunOutcome outcome = take_section(dyn, scene.run, spec, [](const SectionPoint&) {});
    const auto j = nlohmann::json::parse(to_json(spec, 10, 0, nullptr, 0.0, scene, outcome));
    CHECK(j["parameters"]["scheme"] == "auto");
    CHECK(j["parameters"]["step"].is_null());
    CHECK(j["scheme"] == std::string(to_string(plan.scheme)));
    CHECK(j["scheme"] != "auto");
    CHECK(j["step"] == plan.step);
    CHECK(plan.step > 0.0);
}
