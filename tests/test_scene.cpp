#include "gapchain/report.hpp"
#include "gapchain/simulation.hpp"
#include "gapchain/study.hpp"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

using namespace gapchain;

namespace {
std::string error_of(const std::string& text, const std::vector<std::string>& sets = {}) {
    try {
        (void)parse_scene(text, sets);
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}
} // namespace

TEST_CASE("a scene file that opens but cannot be read is named as such, not as malformed JSON") {
    // /proc/self/mem opens, and its first read fails (EIO): the copy through a stream's rdbuf()
    // only failed, as for an empty file, and the parser then said "unexpected end of input".
    CHECK_THROWS_WITH_AS(load_scene("/proc/self/mem"),
                         doctest::Contains("/proc/self/mem: cannot read the scene file"),
                         SceneError);
    CHECK_THROWS_WITH_AS(parse_scene(""), doctest::Contains("malformed JSON"), SceneError);
}

TEST_CASE("an empty scene takes the paper's defaults") {
    const Scene s = parse_scene("{}");
    CHECK(s.reduced.eps == 0.5);
    CHECK(s.run.periods == 1000);
    CHECK(s.run.transient_periods == auto_transient); // MODEL.md §2: the start discarded
    CHECK(s.run.scheme == Scheme::automatic);
    CHECK(s.initial.empty());
}

TEST_CASE("the documented keys are read, and --set overrides them") {
    const Scene s = parse_scene(R"({"model": {"Nm": 5, "fc": 100, "eps": 0.5, "e_r": 0.5},
        "excitation": {"f_r": 1.0},
        "run": {"periods": 1000, "transient_periods": 0, "scheme": "auto", "tolerance": 1e-4}})",
                                {"model.fc=60", "run.scheme=rk4"});
    CHECK(s.reduced.fc == 60);
    CHECK(s.reduced.Nm == 5);
    CHECK(s.run.scheme == Scheme::rk4);
    CHECK(s.run.tolerance == 1e-4);
    for (const char* scheme : {"central_difference", "rkf45", "rk8pd", "exact"})
        CHECK(parse_scene("{}", {std::string("run.scheme=") + scheme}).run.scheme ==
              parse_scheme(scheme));
}

TEST_CASE("short keys get their section; unknown short keys are refused by name") {
    CHECK(scene_key("fc") == "model.fc");
    CHECK(scene_key("f_r") == "excitation.f_r");
    CHECK(scene_key("periods") == "run.periods");
    CHECK(scene_key("accuracy_mode") == "run.accuracy_mode");
    CHECK(scene_key("trajectory_every") == "output.trajectory_every");
    CHECK(scene_key("model.scatter.seed") == "model.scatter.seed");
    CHECK_THROWS_WITH_AS(scene_key("springiness"), doctest::Contains("springiness: unknown key"),
                         SceneError);
    CHECK_THROWS_WITH_AS(scene_key("x", "parameters.x"),
                         doctest::Contains("parameters.x: unknown key"), SceneError);
}

TEST_CASE("physical scenes convert to reduced parameters") {
    const Scene s = parse_scene(R"({"units": "physical",
        "model": {"Nm": 2, "M": 1.0, "K": 39.47841760435743, "C": 1.2566370614359172, "Kc": 3947.841760435743, "e": 0.01},
        "excitation": {"a0": 1.0, "f": 1.5}})");
    REQUIRE(s.physical.has_value());
    CHECK(s.reduced.fc == doctest::Approx(100));
    CHECK(s.reduced.eps == doctest::Approx(0.1));
    CHECK(s.reduced.f_r == doctest::Approx(1.5));
    CHECK(s.reduced.e_r == doctest::Approx(4 * std::numbers::pi * std::numbers::pi * 0.01));
}

TEST_CASE("a physical scene's initial state is in metres and metres per second") {
    // f0 = 1 Hz, a0 = 2 m/s^2: a reduced length is a0 / (4 pi^2 f0^2) metres and a reduced
    // velocity a0 / (4 pi^2 f0) m/s (MODEL.md §3), so 0.1 m and 0.3 m/s are 0.2 pi^2 and 0.6 pi^2.
    const Scene s = parse_scene(R"({"units": "physical",
        "model": {"Nm": 2, "M": 1.0, "K": 39.47841760435743, "C": 1.2566370614359172, "Kc": 3947.841760435743, "e": 0.01},
        "excitation": {"a0": 2.0, "f": 1.5}, "initial": {"u": [0.1, 0.0], "v": [0.0, 0.3]}})");
    const double pi2 = std::numbers::pi * std::numbers::pi;
    REQUIRE(s.initial.size() == 4);
    CHECK(s.initial[0] == doctest::Approx(0.2 * pi2));
    CHECK(s.initial[1] == 0.0);
    CHECK(s.initial[3] == doctest::Approx(0.6 * pi2));
    // The same start written in reduced units runs the same row to the same F_m.
    const Scene r =
        parse_scene(R"({"model": {"Nm": 2, "fc": 100, "eps": 0.1, "e_r": 0.19739208802178717},
        "excitation": {"f_r": 1.5}, "run": {"periods": 40},
        "initial": {"u": [1.9739208802178717, 0.0], "v": [0.0, 5.921762640653615]}})");
    RunOptions o = r.run;
    const double physical_F_m = simulate(s.dynamics(), o, s.initial).F_m;
    CHECK(physical_F_m == doctest::Approx(simulate(r.dynamics(), o, r.initial).F_m).epsilon(1e-9));
    // Out of range, in the scene's own units.
    CHECK(error_of(R"({"initial": {"u": [1e300, 0, 0, 0, 0]}})")
              .find("initial.u[0]: must be in [-1000000000, 1000000000], got 1e+300") !=
          std::string::npos);
    CHECK(error_of(R"({"initial": {"v": [0, 0]}})")
              .find("initial.v: must have model.Nm = 5 "
                    "entries, got 2") != std::string::npos);
    // The entry and the value are named: "[NaN,0]" is no JSON array (JSON has no NaN), and a
    // --set of one entry would have been refused as an unknown key "u[0]" next to a list
    // naming u.
    CHECK(error_of(R"({"model": {"Nm": 2}})", {"initial.u=[NaN,0]"})
              .find("initial.u: must be an array of finite numbers, got \"[NaN,0]\"") !=
          std::string::npos);
    // A value that is neither JSON nor UTF-8 is named too (showing it threw nlohmann's
    // type_error, exit 1 from the tools).
    CHECK(error_of(R"({"model": {"Nm": 2}})", {"initial.u=\xff"})
              .find("initial.u: must be an array of finite numbers, got") != std::string::npos);
    CHECK(error_of(R"({"model": {"Nm": 2}, "initial": {"u": [0, "a"]}})")
              .find("initial.u[1]: must be a finite number, got \"a\"") != std::string::npos);
    CHECK(error_of(R"({"model": {"Nm": 2}})", {"initial.u[0]=5"})
              .find("a key cannot index into an array; give the whole array (initial.u=[...])") !=
          std::string::npos);
}

TEST_CASE("bad input: every class gives one line naming the key") {
    CHECK(error_of("{not json").find("malformed JSON") != std::string::npos);
    CHECK(error_of(R"({"model": {"fcc": 1}})").find("model.fcc: unknown key") != std::string::npos);
    CHECK(error_of(R"({"modle": {}})").find("modle: unknown key") != std::string::npos);
    // One key set twice: the last one used to win, silently.
    CHECK(error_of("{}", {"model.Nm=3", "model.Nm=4"}).find("--set model.Nm: given twice") !=
          std::string::npos);
    // A tool's result given as the scene is named as such, not as an unknown key F_m.
    CHECK(error_of(R"({"F_m": 1.2, "scene": {"model": {"Nm": 2}}})").find("is a gapchain result") !=
          std::string::npos);
    CHECK(error_of(R"({"model": {"Nm": 0}})").find("model.Nm") != std::string::npos);
    CHECK(error_of(R"({"model": {"Nm": 2.5}})").find("model.Nm: must be an integer") !=
          std::string::npos);
    CHECK(error_of(R"({"model": {"fc": "big"}})").find("model.fc: must be a number") !=
          std::string::npos);
    CHECK(error_of(R"({"model": {"fc": 0}})").find("model.fc") != std::string::npos);
    CHECK(error_of(R"({"model": {"eps": -1}})").find("model.eps") != std::string::npos);
    CHECK(error_of(R"({"model": {"e_r": -0.1}})").find("model.e_r") != std::string::npos);
    CHECK(error_of(R"({"excitation": {"f_r": 0}})").find("excitation.f_r") != std::string::npos);
    CHECK(error_of(R"({"run": {"periods": 0}})").find("run.periods") != std::string::npos);
    // An overflowing number names its key (the lexer throws before the value is read).
    CHECK(error_of(R"({"model": {"fc": 1e999}})")
              .find("model.fc: a number must be 0 or finite with |x| in [2.2250738585072014e-308, "
                    "1.7976931348623157e308] (the normal doubles), got \"1e999\"") !=
          std::string::npos);
    CHECK(error_of(R"({"model": {"fc": 1e999}})").find("1e999") != std::string::npos);
    CHECK(error_of("{not json").find("json.exception") == std::string::npos);
    CHECK(error_of("{}", {"model.eps=nan"}).find("model.eps: must be a finite number") !=
          std::string::npos);
    CHECK(error_of("{}", {"model.fc=inf"}).find("model.fc") != std::string::npos);
    // The value as written, not JSON's null for nan and inf; the range, not only "auto".
    CHECK(error_of("{}", {"run.periods=nan"}).find("got nan") != std::string::npos);
    CHECK(error_of("{}", {"run.periods=-inf"}).find("got -inf") != std::string::npos);
    CHECK(error_of("{}", {"model.eps=-nan"}).find("model.eps: must be a finite number") !=
          std::string::npos);
    CHECK(error_of("{}", {"model.eps=abc"})
              .find("model.eps: must be a number in [0, 100], "
                    "got \"abc\"") != std::string::npos);
    CHECK(error_of("{}", {"run.transient_periods=-1"})
              .find("must be \"auto\" or an integer in [0, 999999999], got -1") !=
          std::string::npos);
    CHECK(error_of("{}", {"run.transient_periods=abc"})
              .find("must be \"auto\" or an integer in [0, 999999999], got \"abc\"") !=
          std::string::npos);
    CHECK(error_of(R"({"run": {"scheme": "euler"}})").find("run.scheme: must be one of") !=
          std::string::npos);
    CHECK(error_of(R"({"run": {"accuracy_mode": "fast"}})")
              .find("run.accuracy_mode: must be one of auto, strict") != std::string::npos);
    CHECK(parse_scene("{}", {"run.accuracy_mode=strict"}).run.accuracy_mode ==
          AccuracyMode::strict);
    CHECK(parse_scene("{}").run.accuracy_mode == AccuracyMode::automatic);
    CHECK(error_of(R"({"run": {"periods": 10, "transient_periods": 10}})")
              .find("run.transient_periods") != std::string::npos);
    CHECK(error_of(R"({"initial": {"u": [1, 2]}})").find("initial.u") != std::string::npos);
    CHECK(error_of("{}", {"nodot=3"}).find("--set") != std::string::npos);
    // A NUL or other control character is shown escaped, not cut at ("gapchain-sim: model"),
    // and a path holding one is refused (open() read "fig5.json\0junk" as fig5.json).
    CHECK(error_of(R"({"model\u0000junk": {"Nm": 2}})").find("model\\u0000junk: unknown key") !=
          std::string::npos);
    CHECK(error_of(R"({"run": {"scheme": "rk4\u0000x"}})")
              .find("run.scheme: must hold no control characters") != std::string::npos);
    CHECK_THROWS_WITH_AS((void)load_scene(std::string("data/scenes/fig5.json") + '\0' + "junk"),
                         doctest::Contains("the path holds a NUL byte"), SceneError);
    // A number in the way of a nested key is named whole (it said "eps: ...").
    CHECK(error_of(R"({"model": {"eps": 0.5}})", {"model.eps.x=0.4"})
              .find("model.eps: must be an object to set x") != std::string::npos);
    CHECK_THROWS_AS((void)load_scene("/nonexistent/scene.json"), SceneError);
}

TEST_CASE("numbers JSON cannot hold are named by key, not read as 0 or as malformed text") {
    // 1e-999 reads as 0: eps = 0 ran an undamped row, and fc = 1e-999 said "got 0".
    CHECK(error_of(R"({"model": {"eps": 1e-999}})").find("(the normal doubles), got \"1e-999\"") !=
          std::string::npos);
    CHECK(error_of("{}", {"model.eps=-2e-400"}).find("model.eps: a number must be 0") !=
          std::string::npos);
    // Without an exponent too: 331 zeros after the point read as 0 (an undamped row).
    const std::string tiny = "0." + std::string(330, '0') + "1";
    CHECK(error_of("{}", {"model.eps=" + tiny}).find("model.eps: a number must be 0") !=
          std::string::npos);
    CHECK(error_of(R"({"model": {"eps": )" + tiny + "}}").find("model.eps: a number must be 0") !=
          std::string::npos);
    // And beyond the doubles, as in a file (--set took 1e999 for the string "1e999").
    CHECK(error_of("{}", {"model.fc=1e999"}).find("model.fc: a number must be 0 or finite") !=
          std::string::npos);
    CHECK(error_of(R"({"model": {"Nm": 2}})", {"initial.u=[1,1e-999]"})
              .find("initial.u: a number must be 0") != std::string::npos);
    // The numbers before it are counted, so the key is the underflowing one's, also in an array.
    CHECK(error_of(
              R"({"note": "1e-999", "model": {"Nm": 2, "fc": 50}, "initial": {"u": [1, 3e-500]}})")
              .find("initial.u: a number must be 0") != std::string::npos);
    // Zero written with an exponent is a number like any other; a subnormal is refused (fc =
    // 4.9e-324 passed its range, and the contacts fc / 2 came out 0, named as model.contact).
    CHECK(parse_scene(R"({"model": {"eps": 0e-999}})").reduced.eps == 0.0);
    CHECK(parse_scene(R"({"model": {"eps": 2.3e-308}})").reduced.eps > 0.0);
    CHECK(error_of(R"({"model": {"fc": 4.9e-324}})").find("model.fc: a number must be 0 or") !=
          std::string::npos);
    // NaN and Infinity as other languages write them: JSON has neither; say so, with the key.
    CHECK(error_of(R"({"model": {"fc": NaN}})")
              .find("model.fc: must be a finite number (JSON has no NaN or Infinity), got NaN") !=
          std::string::npos);
    CHECK(error_of(R"({"model": {"Nm": 2}, "initial": {"u": [1, -Infinity]}})")
              .find("initial.u: must be a finite number (JSON has no NaN or Infinity), got "
                    "-Infinity") != std::string::npos);
    // Where a key is due, a NaN is a malformed object, not a value of the key before it.
    CHECK(error_of(R"({"model": {"fc": 1, NaN}})").find("malformed JSON") != std::string::npos);
    CHECK(error_of("NaN").find("malformed JSON") != std::string::npos);
}

TEST_CASE("hostile shapes: deep nesting, huge values and overlapping --set keys are refused by "
          "key") {
    // 100,000 nested arrays under a typed key overflowed the stack where the message printed
    // the value (a segfault).
    const std::string deep = std::string(100000, '[') + std::string(100000, ']');
    CHECK(error_of(R"({"model": {"fc": )" + deep + "}}")
              .find("model.fc: nested more than 64 levels deep") != std::string::npos);
    CHECK(error_of("{}", {"model.scatter=" + deep})
              .find("model.scatter: nested more than 64 levels deep") != std::string::npos);
    // A value in a message is cut: a million-entry array was printed whole.
    std::string many = "[1";
    for (int k = 0; k < 1000000; ++k)
        many += ",1";
    many += "]";
    const std::string message = error_of(R"({"model": {"fc": )" + many + "}}");
    CHECK(message.find("model.fc: must be a number") != std::string::npos);
    CHECK(message.size() < 200);
    // A duplicate inside a --set value names the full key, once.
    CHECK(error_of("{}", {R"(model.scatter={"seed": 1, "seed": 2})"})
              .rfind("model.scatter.seed: duplicate key", 0) == 0);
    // A key and a part of it: the whole replaced the earlier part, silently.
    CHECK(error_of(R"({"model": {"Nm": 2}})",
                   {"model.scatter.seed=2", R"(model.scatter={"clearance": 0.1})"})
              .find("--set model.scatter: overlaps --set model.scatter.seed") != std::string::npos);
    CHECK(error_of(R"({"model": {"Nm": 2}})",
                   {R"(model.scatter={"clearance": 0.1})", "model.scatter.seed=2"})
              .find("overlaps") != std::string::npos);
    // An integer with a leading 0 is refused, as the flags refuse it (model.fc=010 ran fc = 10,
    // octal 8 elsewhere); a decimal fraction with one is a number.
    CHECK(error_of("{}", {"model.fc=010"}).rfind("model.fc: got \"010\": a leading 0", 0) == 0);
    CHECK(error_of("{}", {"model.Nm=-02"}).find("would make it octal") != std::string::npos);
    CHECK(parse_scene("{}", {"model.fc=00.5"}).reduced.fc == 0.5);
    CHECK(parse_scene("{}", {"model.eps=0"}).reduced.eps == 0.0);
}

TEST_CASE("a ground-motion record refuses the steady-state keys it would ignore") {
    // A reviewer's probe (helper-74): run.steady_state true and run.max_steady_period were
    // taken and the run was the plain one.
    const std::string scene = R"({"units": "physical", "model": {"Nm": 2, "M": 100, "K": 1e5,
        "C": 500, "Kc": 5e6, "e": 0.002}, "excitation": {"type": "kanai_tajimi", "a0": 5,
        "ground_frequency": 2.5, "ground_damping": 0.6, "duration": 2, "sample_interval": 0.01,
        "rise": 0.5, "hold": 1, "decay": 0.5}})";
    CHECK_NOTHROW(parse_scene(scene));
    for (const char* set :
         {"run.steady_state=true", "run.steady_tolerance=1e-3", "run.max_steady_period=2"}) {
        CAPTURE(set);
        const std::string key = std::string(set).substr(0, std::string(set).find('='));
        CHECK(error_of(scene, {set})
                  .rfind(key + ": not used with excitation.type = kanai_tajimi", 0) == 0);
    }
}

TEST_CASE("non-uniform rows: arrays equal to the nominal values give the homogeneous run exactly") {
    // The arrays replace eps and e_r, which the array scene therefore does not give.
    const std::string base =
        R"({"model": {"Nm": 3, "fc": 100}, "excitation": {"f_r": 1.1}, "run": {"periods": 40}})";
    const Scene uniform = parse_scene(base, {"model.eps=0.3", "model.e_r=0.2"});
    const Scene arrays = parse_scene(
        base, {"model.mass=[1,1,1]", "model.stiffness=[1,1,1]", "model.damping=[0.3,0.3,0.3]",
               "model.clearance=[0.2,0.2,0.2,0.2]", "model.contact=[1,1,1,1]"});
    CHECK(uniform.uniform());
    REQUIRE_FALSE(arrays.uniform());
    const SimulationResult a = simulate(uniform.dynamics(), uniform.run);
    const SimulationResult b = simulate(arrays.dynamics(), arrays.run);
    CHECK(a.F_m == b.F_m); // bit for bit
    CHECK(a.final_state == b.final_state);
}

TEST_CASE("a simulation result names the row and the start it ran, not only the five numbers") {
    // After --set on arrays, a scatter or a start, the scene file no longer says what ran.
    const std::string base = R"({"model": {"Nm": 2, "fc": 50}})";
    const Scene s = parse_scene(base, {"model.clearance=[0.1,0.3,0.0]", "initial.u=[0.01,-0.02]",
                                       R"(model.scatter={"mass": 0.1, "seed": 3})"});
    const SimulationResult nothing_run;
    const auto j = nlohmann::json::parse(to_json(nothing_run, s));
    REQUIRE(j.contains("chain"));
    CHECK(j["chain"]["clearance"].get<std::vector<double>>() == s.chain().clearance);
    CHECK(j["chain"]["mass"].get<std::vector<double>>() == s.chain().mass);
    CHECK(j["chain"]["contact_law"] == "linear");
    CHECK(j["initial"].get<std::vector<double>>() == s.initial);
    CHECK(j["initial"][1] == -0.02);
    // The paper's row from rest: the five numbers say it all.
    const auto uniform = nlohmann::json::parse(to_json(nothing_run, parse_scene(base)));
    CHECK_FALSE(uniform.contains("chain"));
    CHECK_FALSE(uniform.contains("initial"));
    const auto at_rest = nlohmann::json::parse(
        to_json(nothing_run, parse_scene(base, {"initial.u=[0,0]", "initial.v=[0,0]"})));
    CHECK_FALSE(at_rest.contains("initial"));
}

TEST_CASE("non-uniform rows: per-gap values reach the chain, and a scatter is seeded") {
    const std::string base = R"({"model": {"Nm": 2, "fc": 50, "e_r": 0.1}})";
    const Scene s = parse_scene(
        R"({"model": {"Nm": 2, "fc": 50}})",
        {"model.clearance=[0.1,0.3,0.0]", "model.contact=[2,1,0.5]", "model.mass=[1,4]"});
    const Chain c = s.chain();
    CHECK(c.clearance[1] == 0.3);
    CHECK(c.contact[0] == 100.0);                           // 2 x fc at the left wall
    CHECK(c.contact[1] == 25.0);                            // 1 x fc/2 between the bodies
    CHECK(c.contact[2] == 25.0);                            // 0.5 x fc at the right wall
    CHECK(c.spring[1] == doctest::Approx(c.spring[0] / 4)); // heavier body, same spring
    const Scene s1 = parse_scene(base, {R"(model.scatter={"clearance": 0.1, "seed": 7})"});
    const Scene s2 = parse_scene(base, {R"(model.scatter={"clearance": 0.1, "seed": 7})"});
    const Scene s3 = parse_scene(base, {R"(model.scatter={"clearance": 0.1, "seed": 8})"});
    CHECK(s1.chain().clearance == s2.chain().clearance);
    CHECK(s1.chain().clearance != s3.chain().clearance);
    CHECK(s1.chain().clearance[0] != 0.1);
    // A factor 1 + s z below zero is refused, not clipped (s = 5 set half the clearances to 0).
    CHECK(error_of(base, {R"(model.scatter={"clearance": 5})"})
              .find("model.scatter.clearance: s = 5 draws the factor") != std::string::npos);
    CHECK(
        error_of(base, {R"(model.scatter={"mass": 10, "seed": 4})"}).find("which must stay > 0") !=
        std::string::npos);
}

TEST_CASE("a scalar an array replaces is refused, not shown as if it ran") {
    // e_r = 3 with a clearance array printed "e_r=3" in the header and JSON of a row whose
    // clearances were all 0.2.
    const std::string arrays =
        R"({"model": {"Nm": 3, "clearance": [0.2, 0.2, 0.2, 0.2], "damping": [0.1, 0.1, 0.1]}})";
    CHECK(error_of(arrays, {"model.e_r=3"})
              .find("model.e_r: not read where model.clearance gives every entry") !=
          std::string::npos);
    CHECK(error_of(arrays, {"model.eps=0.5"})
              .find("model.eps: not read where model.damping gives every entry") !=
          std::string::npos);
    CHECK(error_of(R"({"units": "physical", "model": {"Nm": 2, "e": 0.003,
                     "clearance": [0.003, 0.003, 0.003]}})")
              .find("model.e: not read where model.clearance") != std::string::npos);
    // An array from the command line replaces the file's scalar (every shipped scene gives e_r
    // and eps); the result then names no e_r or eps, and the header says "array".
    const Scene over_file =
        parse_scene(R"({"model": {"Nm": 3, "e_r": 0.3, "eps": 0.5}})",
                    {"model.clearance=[0.1,0.2,0.3,0.4]", "model.damping=[1,1,1]"});
    CHECK(over_file.chain().clearance[3] == 0.4);
    CHECK(row_label(over_file) == "Nm=3 fc=100 eps=array e_r=array");
    const auto j = nlohmann::json::parse(to_json(SimulationResult{}, over_file));
    CHECK(j["parameters"]["e_r"].is_null());
    CHECK(j["parameters"]["eps"].is_null());
    CHECK(error_of(R"({"model": {"Nm": 3, "e_r": 0.3}})",
                   {"model.clearance=[0.1,0.2,0.3,0.4]", "model.e_r=0.5"})
              .find("model.e_r: not read") != std::string::npos);
    // The same arrays without the scalars, and a scatter (which scales e_r), are accepted.
    CHECK_FALSE(parse_scene(arrays).uniform());
    CHECK(parse_scene(R"({"model": {"e_r": 0.2, "scatter": {"clearance": 0.1}}})")
              .chain()
              .clearance[0] != 0.2);
}

TEST_CASE("the steady-state settings are refused where no steady-state stop reads them") {
    for (const std::string key : {"steady_tolerance=1e-8", "max_steady_period=4"}) {
        CAPTURE(key);
        const std::string name = "run." + key.substr(0, key.find('='));
        CHECK(error_of(R"({"run": {"steady_state": false}})", {"run." + key})
                  .find(name + ": is read only with run.steady_state true") != std::string::npos);
        CHECK(error_of("{}", {"run.steady_state=false", "run." + key})
                  .find(name + ": is read only") != std::string::npos);
        CHECK(parse_scene("{}", {"run." + key}).run.stop_at_steady_state);
    }
    CHECK_FALSE(parse_scene(R"({"run": {"steady_state": false}})").run.stop_at_steady_state);
}

TEST_CASE("bad arrays fail with a message naming the key") {
    CHECK(error_of(R"({"model": {"Nm": 3, "clearance": [0.1, 0.1]}})")
              .find("model.clearance: must have 4 entries") != std::string::npos);
    CHECK(error_of(R"({"model": {"Nm": 2, "clearance": [0.1, -0.1, 0.1]}})")
              .find("model.clearance: every entry") != std::string::npos);
    CHECK(error_of(R"({"model": {"Nm": 2, "mass": [1, 0]}})").find("model.mass") !=
          std::string::npos);
    CHECK(error_of(R"({"model": {"Nm": 2, "mass": [1, "x"]}})").find("model.mass") !=
          std::string::npos);
    CHECK(error_of(R"({"model": {"scatter": {"clearance": 0.1, "sed": 3}}})")
              .find("model.scatter.sed") != std::string::npos);
}

TEST_CASE("an integer lin range gives exact integers (seeds can be swept)") {
    const Study s = parse_study(R"({"parameters": {"model.scatter.seed": {"lin": [1, 100, 100]}},
        "scene": {"model": {"Nm": 2, "scatter": {"clearance": 0.1}}}})");
    for (long k = 0; k < 100; ++k)
        CHECK(s.axes[0].values[k] == static_cast<double>(k + 1));
}

TEST_CASE("--set reaches nested keys: model.scatter.seed") {
    const Scene a = parse_scene("{}", {"model.scatter.clearance=0.1", "model.scatter.seed=3"});
    const Scene b = parse_scene(R"({"model": {"scatter": {"clearance": 0.1, "seed": 3}}})");
    REQUIRE_FALSE(a.uniform());
    CHECK(a.chain().clearance == b.chain().clearance);
    CHECK(a.chain().clearance !=
          parse_scene("{}", {"model.scatter.clearance=0.1"}).chain().clearance);
    CHECK(error_of(R"({"model": {"Nm": 3}})", {"model.Nm.x=3"}).find("Nm: must be an object") !=
          std::string::npos);
}

TEST_CASE("model.contact_law selects the Hertz law; anything else is refused") {
    const Scene s = parse_scene("{}", {"model.contact_law=hertz"});
    CHECK_FALSE(s.uniform());
    CHECK(s.chain().law == ContactLaw::hertz);
    CHECK(parse_scene("{}", {"model.contact_law=linear"}).uniform());
    CHECK(error_of("{}", {"model.contact_law=spring"})
              .find("model.contact_law: must be one of linear, hertz, hunt_crossley") !=
          std::string::npos);
    const Scene hc =
        parse_scene("{}", {"model.contact_law=hunt_crossley", "model.contact_damping=0.2"});
    CHECK(hc.chain().law == ContactLaw::hunt_crossley);
    CHECK(hc.chain().contact_damping == 0.2);
    CHECK(error_of("{}", {"model.contact_damping=0.2"}).find("model.contact_damping") !=
          std::string::npos);
    CHECK(error_of("{}", {"model.contact_law=hunt_crossley", "model.contact_damping=-1"})
              .find("model.contact_damping") != std::string::npos);
}

TEST_CASE("the keys a row's linear-chain modes do not read") {
    for (const char* key :
         {"model.eps", "model.C", "model.damping", "model.e_r", "model.e", "model.clearance",
          "model.contact_damping", "excitation.f_r", "initial.u"})
        CHECK(key_unread_by_modes(key));
    for (const char* key : {"model.Nm", "model.fc", "model.Kc", "model.mass", "model.stiffness",
                            "model.contact", "model.contact_law", "run.periods"})
        CHECK_FALSE(key_unread_by_modes(key));
}
