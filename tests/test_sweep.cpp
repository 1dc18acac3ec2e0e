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
#include <set>
#include <stdexcept>
#include <string>
#include <thread>

using namespace gapchain;

TEST_CASE("study files: lists, lin and log ranges, and the grid order") {
    const Study s = parse_study(R"({"scene": {"model": {"Nm": 2}},
        "parameters": {"fc": {"log": [1, 100, 3]}, "e_r": {"lin": [0, 1, 3]}, "f_r": [0.5, 1.0]},
        "sample": "grid", "keep": ["F_m", "regime"]})");
    REQUIRE(s.axes.size() == 3);
    CHECK(s.axes[0].values[1] == doctest::Approx(10.0));
    CHECK(s.axes[1].values[2] == doctest::Approx(1.0));
    CHECK(point_count(s) == 18);
    CHECK(s.keep.regime);
    CHECK_FALSE(s.keep.per_body);
    // The first axis varies slowest, the last fastest.
    CHECK(point_values(s, 0) == std::vector<double>{1.0, 0.0, 0.5});
    CHECK(point_values(s, 1) == std::vector<double>{1.0, 0.0, 1.0});
    CHECK(point_values(s, 17)[0] == doctest::Approx(100.0));
    const Scene scene = point_scene(s, 17);
    CHECK(scene.reduced.fc == doctest::Approx(100.0));
    CHECK(scene.reduced.f_r == 1.0);
    CHECK(scene.reduced.Nm == 2);
}

TEST_CASE("random and Latin-hypercube samples are seeded and spread") {
    const std::string axes =
        R"("parameters": {"e_r": {"lin": [0, 1, 10]}, "f_r": {"lin": [1, 2, 10]}})";
    const Study lhs = parse_study(
        "{" + axes + R"(, "sample": {"method": "latin_hypercube", "samples": 10, "seed": 4}})");
    // Each of the 10 values of each axis is used exactly once.
    for (std::size_t a = 0; a < 2; ++a) {
        std::set<double> used;
        for (long i = 0; i < 10; ++i)
            used.insert(point_values(lhs, i)[a]);
        CHECK(used.size() == 10);
    }
    const Study r1 =
        parse_study("{" + axes + R"(, "sample": {"method": "random", "samples": 50, "seed": 9}})");
    const Study r2 = r1;
    CHECK(point_values(r1, 33) == point_values(r2, 33));
}

TEST_CASE("bad studies name the key") {
    CHECK_THROWS_WITH_AS(parse_study(R"({"parameters": {"fc": [0]}})"),
                         doctest::Contains("model.fc"), SceneError);
    CHECK_THROWS_WITH_AS(parse_study(R"({"parameters": {"model.springiness": [1]}})"),
                         doctest::Contains("model.springiness: unknown key"), SceneError);
    CHECK_THROWS_WITH_AS(parse_study(R"({"parameters": {"fc": {"lin": [1, 2]}}})"),
                         doctest::Contains("parameters.fc"), SceneError);
    CHECK_THROWS_WITH_AS(parse_study(R"({"parameters": {}})"), doctest::Contains("parameters"),
                         SceneError);
    CHECK_THROWS_WITH_AS(parse_study(R"({"parameters": {"fc": [1]}, "keep": ["speed"]})"),
                         doctest::Contains("keep"), SceneError);
    CHECK_THROWS_AS(parse_study("{nope"), SceneError);
    // A method that is no string was a raw JSON type error; samples without a method were
    // silently dropped for the grid.
    CHECK_THROWS_WITH_AS(parse_study(R"({"parameters": {"fc": [1]}, "sample": {"method": 5}})"),
                         doctest::Contains("sample.method: must be grid, random or"), SceneError);
    CHECK_THROWS_WITH_AS(
        parse_study(R"({"parameters": {"fc": [1]}, "sample": {"samples": 100, "seed": 3}})"),
        doctest::Contains("sample.samples: applies to random or latin_hypercube"), SceneError);
    // "multistable" is always written, so keeping it is no error; 2e0 starts are 2 starts.
    const Study kept = parse_study(
        R"({"parameters": {"fc": [1]}, "keep": ["F_m", "multistable"], "attractors": 2e0})");
    CHECK(kept.attractor_starts == 2);
    CHECK_THROWS_WITH_AS(parse_study(R"({"parameters": {"fc": [1]}, "attractors": 2.5})"),
                         doctest::Contains("attractors: starts per point"), SceneError);
}

TEST_CASE("a study point above run.max_work is refused when the study is read") {
    // Each axis alone is affordable; the point Nm = 1976 at f_r = 0.01 (100 times the steps per
    // period of f_r = 1) is not. 4 points are checked one by one, 6400 at the axes' corners.
    const std::string scene = R"({"scene": {"model": {"Nm": 1, "fc": 100, "eps": 0.1, "e_r": 0.5},
                                    "run": {"periods": 1000 @MAX@}}, )";
    for (const std::string axes : {R"("parameters": {"Nm": [1, 1976], "f_r": [1, 0.01]}})",
                                   R"("parameters": {"Nm": {"lin": [1, 1976, 80]},
                                                     "f_r": {"lin": [1, 0.01, 80]}}})"}) {
        std::string refused = scene + axes;
        refused.replace(refused.find("@MAX@"), 5, "");
        CHECK_THROWS_WITH_AS(parse_study(refused),
                             doctest::Contains("run.max_work: this run takes up to"), SceneError);
        CHECK_THROWS_WITH_AS(parse_study(refused), doctest::Contains("Nm = 1976, f_r = 0.01"),
                             SceneError);
        std::string allowed = scene + axes;
        allowed.replace(allowed.find("@MAX@"), 5, R"(, "max_work": 1e12)");
        CHECK_NOTHROW((void)parse_study(allowed));
    }
    // An attractor search needs 20 recorded periods: 30 periods pass at f_r = 1 (3 discarded)
    // but not at f_r = 5 (15 discarded), a combination no single axis value shows.
    CHECK_THROWS_WITH_AS(
        parse_study(R"({"scene": {"model": {"Nm": 2, "fc": 10, "eps": 0.5, "e_r": 0.3}},
                        "parameters": {"run.periods": [100, 30], "f_r": [1, 5]},
                        "attractors": 2})"),
        doctest::Contains("(study point with run.periods = 30, f_r = 5)"), SceneError);
    // The same point alone: refused by the run itself, with the same rule.
    const Scene big = parse_scene(R"({"model": {"Nm": 2000, "fc": 100, "eps": 0.1, "e_r": 0.5},
                                      "excitation": {"f_r": 0.01}, "run": {"periods": 1000}})");
    CHECK_THROWS_WITH_AS(require_affordable(big.dynamics(), big.run),
                         doctest::Contains("run.max_work"), std::invalid_argument);
    const Scene small = parse_scene(R"({"model": {"Nm": 1, "fc": 100, "eps": 0.1, "e_r": 0.5},
                                        "excitation": {"f_r": 0.01}, "run": {"periods": 1000}})");
    CHECK_NOTHROW(require_affordable(small.dynamics(), small.run));
}

TEST_CASE("the paper-scale study has 430,080 points") {
    const Study s = load_study(GAPCHAIN_SOURCE_DIR "/data/studies/paper-scale.json");
    CHECK(point_count(s) == 430080);
    long below = 0;
    for (double e : s.axes[3].values)
        below += e < 0.3;
    CHECK(below >= 15);
    CHECK(s.axes[4].values.size() == 56);
}

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
    CHECK(results[0].attractors_found >= 2);
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
    CHECK(header.find(",F_m_orbit,maximum_in_transient") != std::string::npos);
    const std::string flagged = sweep_csv_row(s, results[0]);
    CHECK(flagged.substr(flagged.size() - 2) == ",1");
    REQUIRE(results[0].simulation.F_m_orbit);
    CHECK(flagged.find(',' + std::to_string(*results[0].simulation.F_m_orbit).substr(0, 6)) !=
          std::string::npos);
    CHECK(results[0].simulation.F_m_error >=
          results[0].simulation.F_m - *results[0].simulation.F_m_orbit);
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
        const std::vector<std::string> header = split(sweep_csv_header(s));
        const auto at = std::find(header.begin(), header.end(), name) - header.begin();
        return split(sweep_csv_row(s, r)).at(static_cast<std::size_t>(at));
    };
    REQUIRE(results[0].simulation.steady_state_period);
    CHECK(has_error_estimate(results[0].simulation));
    CHECK(std::stod(field(results[0], "F_m_error")) > 0.0);
    CHECK_FALSE(has_error_estimate(results[1].simulation));
    CHECK(field(results[1], "F_m_error").empty());
    CHECK(std::stod(field(results[1], "F_m")) == doctest::Approx(results[0].simulation.F_m));
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
