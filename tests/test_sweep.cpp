#include "gapchain/report.hpp"
#include "gapchain/run.hpp"
#include "gapchain/study.hpp"
#include "gapchain/sweep.hpp"

#include "detail/parallel.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>

using namespace gapchain;

namespace {

/// The cell of a sweep CSV row under the header's column `name` (empty cells kept).
std::string csv_cell(const std::string& header, const std::string& row, const std::string& name) {
    const auto split = [](const std::string& line) {
        std::vector<std::string> cells(1);
        for (char c : line) {
            if (c == ',')
                cells.emplace_back();
            else
                cells.back().push_back(c);
        }
        return cells;
    };
    const std::vector<std::string> names = split(header);
    const auto k = std::find(names.begin(), names.end(), name) - names.begin();
    return split(row).at(static_cast<std::size_t>(k));
}

} // namespace

TEST_CASE("the parallel loop rethrows a worker's bad input as itself, and stops the others") {
    for (int threads : {1, 2}) {
        std::atomic<long> ran{0};
        // Each index takes a millisecond, as a point of a study takes far longer than the stop.
        auto body = [&](long k) {
            ++ran;
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
            if (k == 3) throw std::invalid_argument("model.fc: must be > 0, got -1");
        };
        CHECK_THROWS_AS(detail::parallel_for(1000, threads, body, [](long) { return true; }),
                        std::invalid_argument);
        CHECK(ran.load() <= 4 + 2 * threads); // those started before the failure, no more
    }
}

TEST_CASE("a study with \"attractors\": F_m_max over the starts is never below the run's F_m") {
    // Fig 13's line at f_r = 3.2 (a torus of F_m 0.385 beside weaker attractors, issue 19) and a
    // contact-free point (eq (20): A = 0.041 < e_r at f_r = 5).
    const Study s = parse_study(R"({"scene": {"model": {"Nm": 5, "fc": 60, "eps": 0.5, "e_r": 0.06},
                                              "run": {"periods": 600, "transient_periods": 300}},
                                    "parameters": {"f_r": [3.2, 5.0]}, "attractors": 24})");
    const StudyScenes scenes(s);
    std::vector<SweepPointResult> results(2);
    run_sweep(
        s, {}, [&](long i) { return sweep_point_input(scenes.scene(i)); },
        [&](const SweepPointResult& r) { results[static_cast<std::size_t>(r.index)] = r; });
    REQUIRE(results[0].F_m_max);
    CHECK(*results[0].F_m_max >= results[0].simulation.F_m);
    CHECK(*results[0].F_m_max == doctest::Approx(0.3853).epsilon(1e-3));
    // The torus settles; the runs towards the period-15 orbit (basin 0.9 over 5000 periods,
    // docs/attractors.md) do not within 600 periods: an unsettled group, counted apart.
    CHECK(results[0].attractors_found >= 1);
    CHECK(results[0].attractors_found + results[0].attractors_unsettled >= 2);
    // The design value carries its error into the row, CSV and Python: the torus's F_m is its
    // run's sample maximum, with that run's spread (> 0, a few per mille at most here).
    CHECK(results[0].F_m_max_error > 0.0);
    CHECK(results[0].F_m_max_error < 0.01 * *results[0].F_m_max);
    const std::string row = sweep_csv_row(s, results[0]);
    const std::string header = sweep_csv_header(s);
    CHECK(std::stod(csv_cell(header, row, "F_m_max_error")) ==
          doctest::Approx(results[0].F_m_max_error).epsilon(1e-9));
    CHECK(*results[1].F_m_max == 0.0);
    CHECK(results[1].attractors_found == 1);
    CHECK_THROWS_WITH_AS(parse_study(R"({"parameters": {"fc": [1]}, "attractors": -3})"),
                         doctest::Contains("attractors"), SceneError);
}

TEST_CASE("a cancel reaches a point that is still running; no cancelled point reaches the sink") {
    // Each point alone would run for minutes (2,000 bodies, 2e4 periods, never settling).
    const Study s =
        parse_study(R"({"scene": {"model": {"Nm": 2000, "fc": 60, "eps": 0.5, "e_r": 0.06},
                                              "run": {"periods": 20000, "steady_state": false,
                                                      "estimate_error": false}},
                                    "parameters": {"f_r": [3.2, 3.3]}})");
    const StudyScenes scenes(s);
    long written = 0, asked = 0;
    const SweepEnd end = run_sweep(
        s, {}, [&](long i) { return sweep_point_input(scenes.scene(i)); },
        [&](const SweepPointResult&) { ++written; }, [&](double) { return ++asked < 3; });
    CHECK(end == SweepEnd::cancelled);
    CHECK(written == 0);
    CHECK(asked == 3);
}

TEST_CASE("keep \"F_m_orbit\": the orbit's maximum and the transient flag, as simulate() says") {
    // The row of the transient check (a start-up peak above its period-1 orbit).
    const Study s = parse_study(R"({"scene": {"model": {"Nm": 10, "fc": 100, "eps": 0.2},
                                              "excitation": {"f_r": 1.125}},
                                    "parameters": {"e_r": [0.35]}, "keep": ["F_m_orbit"]})");
    CHECK(s.keep.orbit);
    const StudyScenes scenes(s);
    std::vector<SweepPointResult> results(1);
    run_sweep(
        s, {}, [&](long i) { return sweep_point_input(scenes.scene(i)); },
        [&](const SweepPointResult& r) { results[static_cast<std::size_t>(r.index)] = r; });
    const std::string header = sweep_csv_header(s);
    CHECK(header.find(",F_m_orbit,F_m_orbit_error,maximum_in_transient") != std::string::npos);
    const std::string flagged = sweep_csv_row(s, results[0]);
    CHECK(flagged.substr(flagged.size() - 2) == ",1");
    REQUIRE(results[0].simulation.F_m_orbit);
    CHECK(flagged.find(',' + std::to_string(*results[0].simulation.F_m_orbit).substr(0, 6)) !=
          std::string::npos);
    CHECK(results[0].simulation.F_m_error >=
          results[0].simulation.F_m - *results[0].simulation.F_m_orbit);
}

TEST_CASE("a point on a cycle longer than run.max_steady_period names it in longer_cycle_period") {
    // The period-18 orbit of test_simulation's long-cycle case (Newton-confirmed there; a
    // plain rk8pd run with max_steady_period 32 agrees): the test's 16 periods miss it.
    const auto study = [](int max_period) {
        return parse_study(R"({"scene": {"model": {"Nm": 5, "fc": 10, "eps": 0.1},
                                         "excitation": {"f_r": 1.6},
                                         "initial": {"u": [0.3, -0.2, 0.1, 0.0, 0.2]},
                                         "run": {"periods": 1000, "max_steady_period": )" +
                           std::to_string(max_period) + R"(}},
                               "parameters": {"e_r": [0.06]}})");
    };
    for (int max_period : {16, 18}) {
        const Study s = study(max_period);
        const StudyScenes scenes(s);
        std::vector<SweepPointResult> results;
        run_sweep(
            s, {}, [&](long i) { return sweep_point_input(scenes.scene(i)); },
            [&](const SweepPointResult& r) { results.push_back(r); });
        REQUIRE(results.size() == 1);
        const std::string header = sweep_csv_header(s);
        const std::string row = sweep_csv_row(s, results[0]);
        CAPTURE(row);
        CHECK(header.find(",steady_state_period,longer_cycle_period") != std::string::npos);
        CHECK(csv_cell(header, row, "steady_state_period") == (max_period == 16 ? "" : "18"));
        CHECK(csv_cell(header, row, "longer_cycle_period") == (max_period == 16 ? "18" : ""));
    }
}

TEST_CASE("an F_m_error nothing estimated is written empty, never as an exact 0") {
    // Fig 5's periodic point: it settles early, so no twin or orbit check widens the error bar.
    const auto study = [](const char* estimate) {
        return parse_study(std::string(R"({"scene": {"model": {"Nm": 5, "fc": 100, "eps": 0.5},
                                                      "run": {"periods": 200, "estimate_error": )") +
                           estimate + R"(}}, "parameters": {"e_r": [0.5]}})");
    };
    const Study s = study("true");
    std::vector<SweepPointResult> results;
    for (const Study& each : {s, study("false")}) {
        const StudyScenes scenes(each);
        run_sweep(
            each, {}, [&](long i) { return sweep_point_input(scenes.scene(i)); },
            [&](const SweepPointResult& r) { results.push_back(r); });
    }
    REQUIRE(results.size() == 2);
    const auto field = [&](const SweepPointResult& r, const std::string& name) {
        return csv_cell(sweep_csv_header(s), sweep_csv_row(s, r), name);
    };
    REQUIRE(results[0].simulation.steady_state_period);
    CHECK(has_error_estimate(results[0].simulation));
    CHECK(std::stod(field(results[0], "F_m_error")) > 0.0);
    CHECK_FALSE(has_error_estimate(results[1].simulation));
    CHECK(field(results[1], "F_m_error").empty());
    CHECK(std::stod(field(results[1], "F_m")) == doctest::Approx(results[0].simulation.F_m));
}

TEST_CASE("a record study's fingerprint covers the record's content, not only its name") {
    // A resumed sweep over a record overwritten in between mixed rows of two records.
    const std::string record = "test_sweep_fingerprint_record.csv";
    const std::string text =
        R"({"scene": {"units": "physical", "model": {"Nm": 2, "M": 100, "K": 1e5, "C": 500,
            "Kc": 5e7, "e": 0.003}, "excitation": {"type": "record", "file": ")" +
        record + R"("}}, "parameters": {"model.e": [0.002, 0.003]}})";
    std::ofstream(record) << "0,0\n0.01,1\n0.02,-1\n0.03,0\n";
    const std::string first = study_fingerprint(parse_study(text, "study.json"));
    CHECK(first == study_fingerprint(parse_study(text, "study.json")));
    std::ofstream(record) << "0,0\n0.01,2\n0.02,-1\n0.03,0\n";
    CHECK(study_fingerprint(parse_study(text, "study.json")) != first);
    std::remove(record.c_str());
}

TEST_CASE("a record study's row leaves f_r empty: a record has no forcing frequency") {
    // The reduced f_r of a record is 1 (its time unit), which the CSV wrote as if it were one
    // (a reviewer's probe, helper-74). A harmonic study's row keeps its f_r.
    const std::string record = "test_sweep_f_r_record.csv";
    std::ofstream(record) << "0,0\n0.01,1\n0.02,-1\n0.03,0\n";
    const std::string scene = R"({"units": "physical", "model": {"Nm": 2, "M": 100, "K": 1e5,
        "C": 500, "Kc": 5e7, "e": 0.003}, "excitation": {"type": "record", "file": ")" +
                              record + R"("}})";
    const Study rec = parse_study(
        R"({"scene": )" + scene + R"(, "parameters": {"model.e": [0.002]}})", "study.json");
    const Study harmonic = parse_study(
        R"({"scene": {"model": {"Nm": 2}, "run": {"periods": 2}}, "parameters": {"f_r": [0.7]}})");
    for (const Study* s : {&rec, &harmonic}) {
        std::vector<SweepPointResult> rows;
        run_study(*s, {}, [&](const SweepPointResult& r) { rows.push_back(r); });
        REQUIRE(rows.size() == 1);
        const std::string cell = csv_cell(sweep_csv_header(*s), sweep_csv_row(*s, rows[0]), "f_r");
        CHECK(cell == (s == &rec ? "" : "0.7"));
    }
    std::remove(record.c_str());
}

TEST_CASE("a results CSV is resumed only by the same study and results version") {
    const Study s = parse_study(R"({"scene": {"model": {"Nm": 2}}, "parameters": {"fc": [1, 2]}})");
    const Study other =
        parse_study(R"({"scene": {"model": {"Nm": 2}}, "parameters": {"fc": [1, 3]}})");
    CHECK(study_fingerprint(s) != study_fingerprint(other));
    CHECK(study_fingerprint(s) == study_fingerprint(s, sweep_results_version));
    CHECK(study_fingerprint(s) != study_fingerprint(s, sweep_results_version - 1));
    // A CSV whose sidecar holds the fingerprint an older results version gave is refused.
    const std::string csv = "test_sweep_resume_version.csv";
    {
        std::ofstream(csv) << sweep_csv_header(s) << "\n";
        std::ofstream(csv + ".json")
            << R"({"fingerprint": ")" << study_fingerprint(s, sweep_results_version - 1) << "\"}";
    }
    CHECK_THROWS_WITH_AS(check_resume(csv, s), doctest::Contains("results version"), SceneError);
    std::ofstream(csv + ".json") << study_json(s);
    CHECK_NOTHROW(check_resume(csv, s));
    std::remove(csv.c_str());
    std::remove((csv + ".json").c_str());
}

TEST_CASE("each force a sweep writes has its error: per_body_error and F_m_error_newton") {
    // A small physical row that settles (a comparison run estimates every contact), and the
    // same with the estimate off (every error cell empty, never 0).
    const auto study = [](const char* estimate) {
        return parse_study(
            std::string(R"({"scene": {"units": "physical", "model": {"Nm": 3, "M": 100,
                "K": 1e5, "C": 500, "Kc": 5e6, "e": 0.002}, "excitation": {"a0": 5, "f": 4},
                "run": {"periods": 300, "transient_periods": 150,
                "estimate_error": )") +
            estimate + R"(}}, "parameters": {"model.e": [0.002]}, "keep": ["per_body"]})");
    };
    std::vector<std::string> rows;
    std::vector<SweepPointResult> results;
    const Study s = study("true");
    const std::string header = sweep_csv_header(s);
    for (const Study& each : {s, study("false, \"multistability_check\": false")}) {
        CHECK(sweep_csv_header(each) == header);
        const StudyScenes scenes(each);
        run_sweep(
            each, {}, [&](long i) { return sweep_point_input(scenes.scene(i)); },
            [&](const SweepPointResult& r) {
                results.push_back(r);
                rows.push_back(sweep_csv_row(each, r));
            });
    }
    REQUIRE(results.size() == 2);
    const auto field = [&](const std::string& row, const std::string& name) {
        return csv_cell(header, row, name);
    };
    const SimulationResult& est = results[0].simulation;
    REQUIRE(has_error_estimate(est));
    REQUIRE(est.contact);
    REQUIRE(est.per_contact_error.size() == 4);
    // Newtons scale F_m and its error alike.
    REQUIRE(results[0].F_m_newton);
    REQUIRE(results[0].F_m_error_newton);
    CHECK(*results[0].F_m_error_newton / est.F_m_error ==
          doctest::Approx(*results[0].F_m_newton / est.F_m).epsilon(1e-12));
    CHECK(std::stod(field(rows[0], "F_m_error_newton")) ==
          doctest::Approx(*results[0].F_m_error_newton).epsilon(1e-9));
    // Body i's left and right errors are those of contacts i and i + 1, each at least F_m_error.
    std::stringstream bodies(field(rows[0], "per_body_error"));
    int i = 0;
    for (std::string body; std::getline(bodies, body, ';'); ++i) {
        const auto bar = body.find('|');
        REQUIRE(bar != std::string::npos);
        CHECK(std::stod(body.substr(0, bar)) ==
              doctest::Approx(est.per_contact_error[static_cast<std::size_t>(i)]).epsilon(1e-9));
        CHECK(
            std::stod(body.substr(bar + 1)) ==
            doctest::Approx(est.per_contact_error[static_cast<std::size_t>(i) + 1]).epsilon(1e-9));
        CHECK(std::stod(body.substr(bar + 1)) >= est.F_m_error * (1 - 1e-9));
    }
    CHECK(i == 3);
    CHECK_FALSE(has_error_estimate(results[1].simulation));
    CHECK(field(rows[1], "F_m_error_newton").empty());
    CHECK(field(rows[1], "per_body_error").empty());
    CHECK_FALSE(field(rows[1], "per_body").empty());
}

TEST_CASE("a sweep row's regime says whether it settled while recording; no orbit, no flag") {
    const Study s = parse_study(R"({"scene": {"model": {"Nm": 2}}, "parameters": {"e_r": [0.1]},
                                    "keep": ["F_m", "regime", "F_m_orbit"]})");
    SweepPointResult r;
    r.values = {0.1};
    r.regime.emplace();
    r.regime->settled_in_record = true;
    const std::string header = sweep_csv_header(s);
    const std::string row = sweep_csv_row(s, r);
    CHECK(std::count(header.begin(), header.end(), ',') == std::count(row.begin(), row.end(), ','));
    CHECK(csv_cell(header, row, "regime_settled_in_record") == "1");
    // A run that settled on no orbit has no orbit maximum to compare: empty, not 0.
    CHECK(csv_cell(header, row, "F_m_orbit").empty());
    CHECK(csv_cell(header, row, "maximum_in_transient").empty());
    r.simulation.F_m_orbit = 0.5;
    CHECK(csv_cell(header, sweep_csv_row(s, r), "maximum_in_transient") == "0");
}
