#include "gapchain/study.hpp"

#include "detail/check.hpp"
#include "detail/json_reader.hpp"
#include "detail/scene_json.hpp"
#include "gapchain/attractors.hpp"
#include "gapchain/grid.hpp"
#include "gapchain/run.hpp"
#include "gapchain/simulation.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <sstream>

namespace gapchain {

using nlohmann::json;
using ojson = nlohmann::ordered_json;

namespace {

std::vector<double> axis_values(const nlohmann::ordered_json& spec, const std::string& key) {
    auto range = [&](const nlohmann::ordered_json& r, bool log) {
        if (!r.is_array() || r.size() != 3 || !r[0].is_number() || !r[1].is_number() ||
            !r[2].is_number_integer())
            throw SceneError(key + ": a range is [from, to, count] with an integer count");
        const double from = r[0].get<double>(), to = r[1].get<double>();
        const long count = r[2].get<long>();
        if (count < 1 || count > 10'000'000 || !std::isfinite(from) || !std::isfinite(to) ||
            (log && (from <= 0.0 || to <= 0.0)))
            throw SceneError(key + ": a range needs a count in [1, 10000000] and finite ends" +
                             std::string(log ? " > 0" : ""));
        // One value cannot span from..to: the end would be dropped silently.
        if (count == 1 && from != to)
            throw SceneError(key + ": a range of count 1 is one value and needs from = to, got [" +
                             detail::format_number(from) + ", " + detail::format_number(to) +
                             ", 1]; give count >= 2 or a list");
        // linspace keeps integer ranges exact, so integer keys such as seeds can be swept.
        const std::vector<double> values =
            log ? logspace(from, to, count) : linspace(from, to, count);
        // [0, 0, 2] or ends a double apart ran the same point again and again.
        for (std::size_t k = 1; k < values.size(); ++k)
            if (values[k] == values[k - 1])
                throw SceneError(key + ": the range [" + detail::format_number(from) + ", " +
                                 detail::format_number(to) + ", " + std::to_string(count) +
                                 "] repeats the value " + detail::format_number(values[k]) +
                                 "; widen it or give a smaller count");
        return values;
    };
    if (spec.is_array()) {
        std::vector<double> v;
        for (const auto& x : spec) {
            if (!x.is_number() || !std::isfinite(x.get<double>()))
                throw SceneError(key + ": values must be finite numbers");
            v.push_back(x.get<double>());
        }
        if (v.empty()) throw SceneError(key + ": needs at least one value");
        // As a range that repeats a value: the same point ran twice, two rows of one point.
        try {
            detail::require_distinct(key, v);
        } catch (const std::invalid_argument& e) {
            throw SceneError(e.what()); // a study's errors are the scene reader's kind
        }
        return v;
    }
    if (spec.is_object() && spec.size() == 1 && spec.contains("lin"))
        return range(spec["lin"], false);
    if (spec.is_object() && spec.size() == 1 && spec.contains("log"))
        return range(spec["log"], true);
    throw SceneError(key + ": must be a list of values, {\"lin\": [from, to, count]} or "
                           "{\"log\": [from, to, count]}");
}

/// Throws SceneError unless every key of object is one of accepted.
void require_keys(const ojson& object, const std::string& prefix,
                  std::initializer_list<const char*> accepted, const std::string& list) {
    for (const auto& [key, value] : object.items()) {
        (void)value;
        bool known = false;
        for (const char* a : accepted)
            known = known || key == a;
        if (!known)
            throw SceneError(prefix + detail::visible(key) +
                             ": unknown key; accepted keys here: " + list);
    }
}

/// "sample": "grid" or {"method", "samples", "seed"}.
void read_sampling(const ojson& sample, Study& s) {
    if (sample == "grid") {
        s.sampling = Sampling::grid;
        return;
    }
    if (!sample.is_object())
        throw SceneError("sample: must be \"grid\" or {\"method\": \"random\" or "
                         "\"latin_hypercube\", \"samples\": N, \"seed\": S}, got " +
                         detail::shown_json(sample));
    require_keys(sample, "sample.", {"method", "samples", "seed"}, "method, samples, seed");
    if (sample.contains("method") && !sample["method"].is_string())
        throw SceneError("sample.method: must be grid, random or latin_hypercube, got " +
                         detail::shown_json(sample["method"]));
    const std::string method = sample.value("method", std::string("grid"));
    if (method == "random")
        s.sampling = Sampling::random;
    else if (method == "latin_hypercube")
        s.sampling = Sampling::latin_hypercube;
    else if (method != "grid")
        throw SceneError("sample.method: must be grid, random or latin_hypercube, got \"" + method +
                         "\"");
    // A grid takes every point: samples and seed would be ignored (a study that gave them but
    // no method silently ran the grid).
    if (s.sampling == Sampling::grid) {
        if (sample.contains("samples") || sample.contains("seed"))
            throw SceneError(std::string("sample.") +
                             (sample.contains("samples") ? "samples" : "seed") +
                             ": applies to random or latin_hypercube sampling; give "
                             "sample.method (the grid takes every point)");
        return;
    }
    if (!sample.contains("samples") || !sample["samples"].is_number_integer())
        throw SceneError("sample.samples: an integer in [1, 10000000] is required");
    s.samples = sample["samples"].get<long>();
    const long limit = s.sampling == Sampling::latin_hypercube ? 20000 : 10'000'000;
    if (s.samples < 1 || s.samples > limit)
        throw SceneError("sample.samples: must be in [1, " + std::to_string(limit) + "], got " +
                         std::to_string(s.samples));
    if (sample.contains("seed")) {
        if (!sample["seed"].is_number_unsigned())
            throw SceneError("sample.seed: must be a non-negative integer");
        s.seed = sample["seed"].get<unsigned long long>();
    }
}

/// "attractors": starts per point for F_m_max, an integer in [0, 10000].
/// An integral number written as 1e3 counts, as it does for the scene's integer keys.
long read_attractor_starts(const ojson& value) {
    const double starts = value.is_number() ? value.get<double>() : -1.0;
    if (!(starts >= 0.0 && starts <= 10000.0 && starts == std::floor(starts)))
        throw SceneError("attractors: starts per point, an integer in [0, 10000], got " +
                         detail::shown_json(value));
    return static_cast<long>(starts);
}

/// "keep": the result names a study writes (F_m always).
KeptResults read_kept(const ojson& keep) {
    if (!keep.is_array()) throw SceneError("keep: must be a list of result names");
    // A keep list names all it keeps: the defaults (steady_state, wall_time) only without one.
    KeptResults kept;
    kept.steady_state = false;
    kept.wall_time = false;
    for (const auto& k : keep) {
        const std::string name = k.is_string() ? k.get<std::string>() : "";
        if (name == "F_m" || name == "multistable") continue; // always written
        if (name == "per_body")
            kept.per_body = true;
        else if (name == "regime")
            kept.regime = true;
        else if (name == "steady_state_period")
            kept.steady_state = true;
        else if (name == "wall_time")
            kept.wall_time = true;
        else if (name == "F_m_orbit")
            kept.orbit = true;
        else
            throw SceneError("keep: entries must be F_m, multistable, per_body, regime, "
                             "steady_state_period, wall_time or F_m_orbit, got " +
                             detail::shown_json(k));
    }
    return kept;
}

/// The scene key a study axis names (short keys: scene_key()).
std::string full_key(const std::string& key) {
    return scene_key(key, "parameters." + key);
}

/// An axis value as the JSON number a scene file would hold: integral values as integers (so
/// that integer keys such as Nm or seeds accept them), others as doubles.
json axis_value(double v) {
    if (v == std::floor(v) && std::abs(v) < 1e15)
        return v >= 0.0 ? json(static_cast<std::uint64_t>(v)) : json(static_cast<std::int64_t>(v));
    return json(v);
}

/// An attractor search needs a recorded window of 20 periods (attractors.hpp's validate()).
void check_attractor_window(const Scene& scene, long starts) {
    AttractorOptions options;
    options.samples = starts;
    options.run = scene.run;
    try {
        validate(scene.reduced, options);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string("attractors: ") + e.what());
    }
}

/// Axes that change nothing (every row the same, exit 0): output.* (a sweep writes no
/// trajectory) and a seed with no scatter spread above 0 in the scene or the parameters
/// ({"seed": 1} alone spreads nothing).
void check_axes_change_something(const Study& s, const json& root) {
    bool spreads = std::any_of(s.axes.begin(), s.axes.end(), [](const auto& a) {
        const std::string k = full_key(a.key);
        return k.starts_with("model.scatter.") && k != "model.scatter.seed" &&
               std::any_of(a.values.begin(), a.values.end(), [](double v) { return v > 0; });
    });
    if (root.is_object() && root.contains("model") && root["model"].is_object() &&
        root["model"].contains("scatter") && root["model"]["scatter"].is_object())
        for (const auto& [k, v] : root["model"]["scatter"].items())
            spreads = spreads || (k != "seed" && v.is_number() && v.get<double>() > 0);
    for (const auto& axis : s.axes) {
        const std::string key = full_key(axis.key);
        if (key.starts_with("output."))
            throw SceneError("parameters." + axis.key + ": a sweep writes no trajectory, so it " +
                             "does not read " + key);
        if (key == "model.scatter.seed" && !spreads)
            throw SceneError("parameters." + axis.key + ": nothing to seed (no model.scatter " +
                             "spread above 0 in the scene or the parameters), every row would " +
                             "be the same row; give model.scatter its clearance, contact, mass " +
                             "or stiffness spread");
    }
}

/// Refuses an axis over a key whose values are text or true/false (run.scheme,
/// run.steady_state, ...): an axis holds numbers, so its values were refused one by one ("must
/// be finite numbers", then "run.scheme: must be a string"), after the key had been offered.
void require_numeric_key(const std::string& axis_key) {
    static const std::array<const char*, 9> not_numbers{
        "run.scheme",        "run.steady_state",         "run.estimate_error",
        "run.accuracy_mode", "run.multistability_check", "model.contact_law",
        "excitation.type",   "excitation.file",          "excitation.unit"};
    const std::string key = full_key(axis_key);
    if (std::find(not_numbers.begin(), not_numbers.end(), key) != not_numbers.end())
        throw SceneError("parameters." + axis_key + ": cannot be swept (an axis holds numbers, " +
                         "and " + key + " takes text or true/false); run one study for each " +
                         "of its values");
}

/// An axis over the number a model array replaces (e_r or a physical e under model.clearance,
/// eps under model.damping) would label one row with many values: a sweep of e_r over a
/// clearance array wrote four values and ran one row four times.
void check_axes_read(const Study& s) {
    const json root = json::parse(s.scene_json, nullptr, false);
    check_axes_change_something(s, root);
    if (!root.is_object() || !root.contains("model") || !root["model"].is_object()) return;
    const json& model = root["model"];
    for (const auto& axis : s.axes) {
        const std::string key = full_key(axis.key);
        const char* array = key == "model.e_r" || key == "model.e" ? "clearance"
                            : key == "model.eps"                   ? "damping"
                                                                   : nullptr;
        if (array && model.contains(array))
            throw SceneError("parameters." + axis.key + ": not read where the scene's model." +
                             array + " gives every entry (the array replaces it); vary the " +
                             "array's entries, or its scatter (model.scatter.seed), instead");
    }
}

/// Every axis value must make a valid scene on its own: fail before any point runs.
void check_axis_values(const Study& s) {
    check_axes_read(s);
    for (const auto& axis : s.axes)
        for (double v : axis.values) {
            Study one = s;
            one.axes = {{axis.key, {v}}};
            one.sampling = Sampling::grid;
            const Scene scene = point_scene(one, 0);
            if ((s.keep.regime || s.attractor_starts > 0) &&
                (!scene.uniform() || !scene.harmonic()))
                throw SceneError(
                    std::string(s.keep.regime ? "keep: \"regime\"" : "attractors") + " needs " +
                    (scene.harmonic() ? "the paper's uniform row with the linear contact law "
                                        "(no model arrays, scatter or contact_law)"
                                      : "harmonic forcing (a forcing period), not a record") +
                    (s.keep.regime ? "; drop \"regime\" from keep" : "; drop \"attractors\""));
        }
}

/// A point above run.max_work, or with an attractor search on fewer than 20 recorded periods,
/// would stop a sweep when its turn comes, hours in: refuse it before any file is written. A
/// study of up to max_checked points is checked point by point; a larger one at the corners of
/// its axes (each axis at its smallest and largest value), where the work peaks and the
/// recorded window is shortest, because they change monotonically with every key that changes
/// them (Nm, periods, fc, f_r, eps, tolerance, step). A point the corners miss is still refused
/// when it runs.
void check_points(const Study& s, long max_checked) {
    Study checked = s;
    if (point_count(s) > max_checked) {
        checked.sampling = Sampling::grid;
        for (auto& axis : checked.axes) {
            const auto [low, high] = std::minmax_element(axis.values.begin(), axis.values.end());
            axis.values = *low == *high ? std::vector<double>{*low} : std::vector{*low, *high};
        }
    }
    const StudyScenes scenes(checked);
    for (long i = 0; i < point_count(checked); ++i) {
        const Scene scene = scenes.scene(i);
        try {
            require_simulation_affordable(scene.dynamics(), scene.run);
            if (s.attractor_starts > 0) check_attractor_window(scene, s.attractor_starts);
        } catch (const std::invalid_argument& e) {
            std::string where;
            const std::vector<double> values = point_values(checked, i);
            for (std::size_t a = 0; a < checked.axes.size(); ++a)
                where += (a ? ", " : "") + checked.axes[a].key + " = " +
                         detail::format_number(values[a]);
            throw SceneError(std::string(e.what()) + " (study point with " + where + ")");
        }
    }
}

} // namespace

Study parse_study(const std::string& text, const std::string& source) {
    const ojson root = detail::parse_json_strictly<ojson>(text, source);
    if (!root.is_object()) throw SceneError(source + ": a study is a JSON object");
    require_keys(root, "", {"scene", "parameters", "sample", "keep", "attractors"},
                 "scene, parameters, sample, keep, attractors");
    Study s;
    s.source = source;
    if (root.contains("scene")) {
        if (!root["scene"].is_object()) throw SceneError("scene: must be a JSON object");
        s.scene_json = root["scene"].dump();
    }
    (void)parse_scene(s.scene_json, {}, source + " scene");
    if (!root.contains("parameters") || !root["parameters"].is_object() ||
        root["parameters"].empty())
        throw SceneError("parameters: must be an object with at least one swept key");
    for (const auto& [key, spec] : root["parameters"].items()) {
        for (const auto& axis : s.axes)
            if (full_key(axis.key) == full_key(key))
                throw SceneError("parameters." + key + ": parameter given twice (also as " +
                                 axis.key + "); keep one");
        require_numeric_key(key);
        s.axes.push_back({key, axis_values(spec, "parameters." + key)});
    }
    if (root.contains("sample")) read_sampling(root["sample"], s);
    if (root.contains("keep")) s.keep = read_kept(root["keep"]);
    if (root.contains("attractors")) s.attractor_starts = read_attractor_starts(root["attractors"]);
    const long n = point_count(s);
    if (n < 1 || n > 100'000'000)
        throw SceneError("parameters: the study must have 1 .. 1e8 points");
    check_axis_values(s);
    check_points(s, 4096);
    return s;
}

Study load_study(const std::string& path) {
    return parse_study(detail::read_text_file(path, "study"), path);
}

struct StudyScenes::BaseScene {
    json root;
};

StudyScenes::StudyScenes(const Study& study)
    : m_study(study), m_base(std::make_unique<BaseScene>()) {
    try {
        m_base->root = json::parse(study.scene_json);
    } catch (const json::exception& e) {
        throw SceneError(study.source + " scene: malformed JSON: " + detail::plain_what(e));
    }
}

StudyScenes::~StudyScenes() = default;

Scene StudyScenes::scene(long index) const {
    const std::vector<double> v = point_values(m_study, index);
    json root = m_base->root;
    for (std::size_t a = 0; a < m_study.axes.size(); ++a)
        detail::set_scene_key(root, full_key(m_study.axes[a].key), axis_value(v[a]),
                              "parameters." + m_study.axes[a].key);
    return detail::scene_from_parsed_json(std::move(root), {},
                                          m_study.source + " point " + std::to_string(index));
}

Scene point_scene(const Study& study, long index) {
    return StudyScenes(study).scene(index);
}

SweepPointInput sweep_point_input(const Scene& scene) {
    return {scene.dynamics(), scene.run,       scene.initial,   scene.reduced,
            scene.physical,   scene.uniform(), scene.harmonic()};
}

SweepEnd run_study(const Study& study, const SweepSelection& selection,
                   const std::function<void(const SweepPointResult&)>& sink,
                   const ProgressCallback& progress) {
    const StudyScenes scenes(study);
    return run_sweep(
        study, selection, [&](long index) { return sweep_point_input(scenes.scene(index)); }, sink,
        progress);
}

} // namespace gapchain
