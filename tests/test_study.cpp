#include "gapchain/report.hpp"
#include "gapchain/run.hpp"
#include "gapchain/scene.hpp"
#include "gapchain/study.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>
#include <string>
#include <unistd.h>

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
    // A range of one value ran only its start, its end silently dropped.
    CHECK_THROWS_WITH_AS(parse_study(R"({"parameters": {"e_r": {"lin": [0.2, 1, 1]}}})"),
                         doctest::Contains("count 1 is one value and needs from = to"), SceneError);
    CHECK(point_count(parse_study(R"({"parameters": {"e_r": {"log": [0.2, 0.2, 1]}}})")) == 1);
    // A range that repeats a value ran the same points again.
    for (const char* range : {R"({"lin": [0, 0, 2]})", R"({"lin": [1, 1.0000000000000002, 3]})",
                              R"({"log": [1, 1, 2]})"})
        CHECK_THROWS_WITH_AS(parse_study(std::string(R"({"parameters": {"e_r": )") + range + "}}"),
                             doctest::Contains("parameters.e_r: the range"), SceneError);
    CHECK_THROWS_WITH_AS(parse_study(R"({"parameters": {"fc": [1]}, "keep": ["speed"]})"),
                         doctest::Contains("keep"), SceneError);
    CHECK_THROWS_AS(parse_study("{nope"), SceneError);
    // A method that is no string was a raw JSON type error; samples without a method were
    // silently dropped for the grid.
    CHECK_THROWS_WITH_AS(parse_study(R"({"parameters": {"fc": [1]}, "sample": {"method": 5}})"),
                         doctest::Contains("sample.method: must be grid, random or"), SceneError);
    // A misspelled sampling named neither the methods nor what was given (helper-82).
    CHECK_THROWS_WITH_AS(parse_study(R"({"parameters": {"fc": [1]}, "sample": "gird"})"),
                         doctest::Contains(R"("random" or "latin_hypercube", "samples": N, )"
                                           R"("seed": S}, got "gird")"),
                         SceneError);
    CHECK_THROWS_WITH_AS(
        parse_study(R"({"parameters": {"fc": [1]}, "sample": {"samples": 100, "seed": 3}})"),
        doctest::Contains("sample.samples: applies to random or latin_hypercube"), SceneError);
    // "multistable" is always written, so keeping it is no error; 2e0 starts are 2 starts.
    const Study kept = parse_study(
        R"({"parameters": {"fc": [1]}, "keep": ["F_m", "multistable"], "attractors": 2e0})");
    CHECK(kept.attractor_starts == 2);
    CHECK_THROWS_WITH_AS(parse_study(R"({"parameters": {"fc": [1]}, "attractors": 2.5})"),
                         doctest::Contains("attractors: starts per point"), SceneError);
    // An axis over a number a model array replaces: one row ran under four labels of e_r.
    CHECK_THROWS_WITH_AS(
        parse_study(R"({"scene": {"model": {"Nm": 2, "clearance": [0.2, 0.2, 0.2]}},
                        "parameters": {"e_r": [0.1, 0.5]}})"),
        doctest::Contains("parameters.e_r: not read where the scene's model.clearance"),
        SceneError);
    CHECK_THROWS_WITH_AS(parse_study(R"({"scene": {"model": {"Nm": 2, "damping": [0.2, 0.2]}},
                                         "parameters": {"model.eps": [0.1, 0.5]}})"),
                         doctest::Contains("parameters.model.eps: not read"), SceneError);
    // A scatter varies about the number: both are read.
    CHECK(point_count(parse_study(R"({"scene": {"model": {"Nm": 2, "scatter": {"clearance": 0.1}}},
                                      "parameters": {"e_r": [0.1, 0.5]}})")) == 2);
    // Axes that change nothing: every row the same, exit 0.
    CHECK_THROWS_WITH_AS(
        parse_study(R"({"parameters": {"output.trajectory_every": [1, 5]}})"),
        doctest::Contains("parameters.output.trajectory_every: a sweep writes no trajectory"),
        SceneError);
    CHECK_THROWS_WITH_AS(parse_study(R"({"parameters": {"model.scatter.seed": [1, 2]}})"),
                         doctest::Contains("parameters.model.scatter.seed: nothing to seed"),
                         SceneError);
    CHECK_THROWS_WITH_AS(parse_study(R"({"scene": {"model": {"scatter": {"seed": 1}}},
                                         "parameters": {"model.scatter.seed": [1, 2],
                                                        "model.scatter.mass": [0]}})"),
                         doctest::Contains("nothing to seed"), SceneError);
    CHECK(point_count(parse_study(R"({"parameters": {"model.scatter.seed": [1, 2],
                                      "model.scatter.mass": [0.1]}})")) == 2);
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

TEST_CASE("a study point whose error estimate is above run.max_work is refused when read") {
    // 40 periods of 60 steps fit 5000 body-steps for Nm 2; the comparison's 120 do not. The
    // sweep wrote its CSV and sidecar, then stopped at the first point.
    const std::string study = R"({"scene": {"model": {"Nm": 2, "eps": 0.5, "fc": 60},
        "run": {"periods": 40, "transient_periods": 20, "max_work": 5000 @MORE@}},
        "parameters": {"e_r": [0.05, 0.1], "f_r": [2.9, 3.0]}})";
    std::string refused = study;
    refused.replace(refused.find("@MORE@"), 6, "");
    CHECK_THROWS_WITH_AS(parse_study(refused),
                         doctest::Contains("the error estimate's comparison run"), SceneError);
    std::string allowed = study;
    allowed.replace(allowed.find("@MORE@"), 6, R"(, "estimate_error": false)");
    CHECK_NOTHROW((void)parse_study(allowed));
}

TEST_CASE("a study's record file is read next to the study, wherever the sweep runs from") {
    // The CSV header parsed the study's scene as if from the working folder: a study in
    // another folder was refused ("rec.csv: cannot read"), or read a stray rec.csv there.
    const auto dir = std::filesystem::temp_directory_path() /
                     ("gapchain-study-record-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    {
        std::ofstream record(dir / "rec.csv");
        record << "t,a\n";
        for (int i = 0; i <= 400; ++i)
            record << i * 0.005 << ',' << std::sin(2 * 3.141592653589793 * 5 * i * 0.005) << '\n';
    }
    std::ofstream(dir / "study.json")
        << R"({"scene": {"units": "physical", "model": {"Nm": 2, "M": 1, "K": 1000, "C": 1,
                          "Kc": 100000, "e": 0.001},
                "excitation": {"type": "record", "file": "rec.csv", "unit": "m/s2", "a0": 1}},
               "parameters": {"model.e": [0.001, 0.002]}})";
    REQUIRE_FALSE(std::filesystem::exists("rec.csv"));
    const Study study = load_study((dir / "study.json").string());
    CHECK(sweep_csv_header(study).find("F_m_newton") != std::string::npos);
    std::filesystem::remove_all(dir);
}

TEST_CASE("a value given twice in an axis is refused, as in a range") {
    CHECK_THROWS_WITH_AS(parse_study(R"({"parameters": {"e_r": [0.1, 0.2, 0.1]}})"),
                         doctest::Contains("parameters.e_r: the value 0.1 is given twice"),
                         SceneError);
    CHECK(point_count(parse_study(R"({"parameters": {"e_r": [0.1, 0.2]}})")) == 2);
}

TEST_CASE("an axis over a key of text or true/false is refused by name") {
    for (const std::string key :
         {"scheme", "run.scheme", "steady_state", "estimate_error", "multistability_check",
          "accuracy_mode", "model.contact_law", "excitation.type"}) {
        CAPTURE(key);
        for (const std::string values : {R"(["a", "b"])", "[1, 2]"}) {
            std::string message;
            try {
                (void)parse_study(R"({"parameters": {")" + key + R"(": )" + values + "}}");
            } catch (const SceneError& e) {
                message = e.what();
            }
            CHECK(message.find("parameters." + key + ": cannot be swept") != std::string::npos);
        }
    }
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
