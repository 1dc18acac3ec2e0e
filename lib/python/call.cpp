#include "call.hpp"

#include <pybind11/stl.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <stdexcept>

namespace gapchain::python {

namespace {

// A keyword's value as the text of a "section.key=value" override: floats by repr (which
// round-trips and writes nan / inf as the scene parser reads them), bools and integers as
// JSON, everything else through gapchain._scene_json (strings, lists, dicts, NumPy values; a
// value JSON cannot hold raises ValueError naming the key).
std::string override_text(const std::string& key, const py::handle& value) {
    if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
    const py::module_ numbers = py::module_::import("numbers");
    if (py::isinstance(value, numbers.attr("Integral")))
        return py::str(py::int_(py::reinterpret_borrow<py::object>(value)));
    if (py::isinstance(value, numbers.attr("Real")))
        return py::repr(py::float_(py::reinterpret_borrow<py::object>(value)));
    return py::module_::import("gapchain").attr("_scene_json")(value, key).cast<std::string>();
}

// A str or os.PathLike as a path string, or nothing.
std::optional<std::string> as_path(const py::object& object) {
    if (py::isinstance<py::str>(object)) return object.cast<std::string>();
    if (py::hasattr(object, "__fspath__"))
        return py::module_::import("os").attr("fspath")(object).cast<std::string>();
    return std::nullopt;
}

// Through gapchain._scene_json: NumPy values as JSON numbers, and a non-finite number raises
// ValueError naming its key (json.dumps would write NaN, which no JSON parser names).
std::string json_text(const py::object& dict) {
    return py::module_::import("gapchain").attr("_scene_json")(dict).cast<std::string>();
}

std::string type_name(const py::object& object) {
    return py::str(py::type::of(object).attr("__name__"));
}

} // namespace

Scene to_scene(const py::object& scene, const py::kwargs& keys) {
    std::vector<std::string> overrides;
    // Keyword -> dotted key: fc and model.fc name one key, which the scene reader would call
    // "--set ... given twice" in the CLI's words.
    std::map<std::string, std::string> keyword_of;
    for (const auto& [key, value] : keys) {
        const std::string keyword = key.cast<std::string>();
        const std::string name = scene_key(keyword);
        if (const auto [it, added] = keyword_of.emplace(name, keyword); !added)
            throw std::invalid_argument(name + ": given twice, as the keywords " + it->second +
                                        " and " + keyword);
        overrides.push_back(name + "=" + override_text(name, value));
    }
    if (scene.is_none()) return parse_scene("{}", overrides, "<built-in>");
    if (py::isinstance<py::dict>(scene)) return parse_scene(json_text(scene), overrides, "<dict>");
    if (const auto path = as_path(scene)) return load_scene(*path, overrides);
    throw SceneError("scene: must be None, a dict or the path of a scene file, got " +
                     type_name(scene));
}

void refuse_swept_keys(const py::kwargs& keys, const std::string& param,
                       const std::string& function, const std::string& over) {
    const auto replaced = keys_replaced_by(parse_swept_parameter(param));
    for (const auto& [key, value] : keys) {
        const std::string name = key.cast<std::string>();
        const std::string dotted = scene_key(name);
        if (dotted == replaced[0] || dotted == replaced[1])
            throw std::invalid_argument(name + ": " + function + "() varies " + param +
                                        " itself, " + over + "; drop the " + name + " keyword");
    }
}

Scene to_swept_scene(const py::object& scene, const std::string& param, const py::kwargs& keys,
                     const std::string& function) {
    refuse_swept_keys(keys, param, function, "from from_ to to");
    return to_scene(scene, keys);
}

void refuse_run_keys(const py::kwargs& keys, const std::string& function,
                     const std::vector<std::string>& read, const std::string& instead,
                     const std::vector<std::string>& unread) {
    std::string listed;
    for (const auto& key : read)
        listed += (listed.empty() ? "" : ", ") + (key == "run." ? "the run section" : key);
    for (const auto& key : unread)
        listed += (key == unread.front() ? " except " : ", ") + key;
    for (const auto& [key, value] : keys) {
        const std::string name = key.cast<std::string>();
        const std::string dotted = scene_key(name);
        if (dotted.rfind("run.", 0) != 0 && dotted.rfind("output.", 0) != 0) continue;
        const bool is_read = std::find(unread.begin(), unread.end(), dotted) == unread.end() &&
                             std::any_of(read.begin(), read.end(), [&](const std::string& r) {
                                 return r.back() == '.' ? dotted.rfind(r, 0) == 0 : dotted == r;
                             });
        if (!is_read)
            throw std::invalid_argument(name + ": " + function + "() does not read it (" + instead +
                                        ")" + (listed.empty() ? "" : "; it reads " + listed) +
                                        "; drop the " + name + " keyword");
    }
}

const ReducedParameters& paper_row(const Scene& scene, const std::string& function) {
    require_paper_row(scene, function + "()");
    return scene.reduced;
}

Study to_study(const py::object& study) {
    if (py::isinstance<py::dict>(study)) return parse_study(json_text(study), "<dict>");
    if (const auto path = as_path(study)) return load_study(*path);
    throw SceneError("study: must be a dict or the path of a study file, got " + type_name(study));
}

ProgressCallback Call::callback() {
    return [this](double fraction) {
        py::gil_scoped_acquire acquire;
        if (m_error) return false;
        try {
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            if (!m_progress.is_none()) m_progress(fraction);
        } catch (py::error_already_set& e) {
            m_error.emplace(std::move(e));
            return false;
        }
        return true;
    };
}

void Call::keep_partial(const std::function<py::object()>& partial) {
    try {
        py::setattr(m_error->value(), "partial", partial());
    } catch (const std::exception&) {
        // error_already_set fetched (and so cleared) the conversion's own Python error.
    }
}

int choice(const std::string& value, const std::string& keyword,
           const std::vector<std::string>& names) {
    std::string list;
    for (std::size_t i = 0; i < names.size(); ++i) {
        if (names[i] == value) return static_cast<int>(i);
        list += (i ? ", " : "") + names[i];
    }
    throw std::invalid_argument(keyword + ": must be one of " + list + ", got \"" + value + "\"");
}

py::array_t<double> array(const std::vector<double>& values) {
    py::array_t<double> out(static_cast<py::ssize_t>(values.size()));
    if (!values.empty())
        std::memcpy(out.mutable_data(), values.data(), values.size() * sizeof(double));
    return out;
}

py::array_t<double> matrix(const std::vector<double>& data, std::size_t rows, std::size_t cols) {
    py::array_t<double> out({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
    if (rows * cols > 0) std::memcpy(out.mutable_data(), data.data(), rows * cols * sizeof(double));
    return out;
}

py::dict per_contact_dict(const std::vector<ContactMaximum>& contacts) {
    using C = ContactMaximum;
    py::dict d;
    d["force"] = column<double>(contacts, [](const C& c) { return c.force; });
    d["time"] = column<double>(contacts, [](const C& c) { return c.time; });
    d["impacts"] = column<long>(contacts, [](const C& c) { return c.impacts; });
    return d;
}

py::dict run_dict(const Scene& scene) {
    py::dict d;
    d["periods"] = scene.run.periods;
    d["transient_periods"] = scene.run.transient_periods == auto_transient
                                 ? py::object(py::str("auto"))
                                 : py::object(py::int_(scene.run.transient_periods));
    d["scheme"] = std::string(to_string(scene.run.scheme));
    d["tolerance"] = scene.run.tolerance;
    d["source"] = scene.source;
    return d;
}

AttractorOptions design_search(const Scene& scene, const RunOptions& run,
                               const std::string& function, long attractors,
                               std::optional<std::uint64_t> seed, std::optional<double> box,
                               std::optional<int> threads) {
    AttractorOptions search;
    // 0 is no search; the search's own range starts at 1.
    if (attractors < 0 || attractors > 10'000'000)
        throw std::invalid_argument("attractors: must be an integer in [0, 10000000] (0: no "
                                    "search), got " +
                                    std::to_string(attractors));
    if (attractors != 0) {
        search.samples = attractors;
        search.seed = seed.value_or(search.seed);
        search.box = box.value_or(search.box);
        search.threads = threads.value_or(search.threads);
        search.run = run;
        // Not paper_row(): "simulate(attractors=...)()" read as a call of a call.
        require_paper_row(scene, function + "() with attractors=" + std::to_string(attractors));
        validate(scene.reduced, search);
    } else if (seed || box || threads) {
        // Given at its default value too: a seed without a search is a mistake either way.
        throw std::invalid_argument(std::string(seed  ? "seed"
                                                : box ? "box"
                                                      : "threads") +
                                    ": applies to the attractor search only; give attractors, "
                                    "1 .. 1e7");
    }
    return search;
}

} // namespace gapchain::python
