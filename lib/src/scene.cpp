#include "gapchain/scene.hpp"

#include "detail/check.hpp"
#include "detail/json_reader.hpp"
#include "detail/random.hpp"
#include "detail/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>
#include <unistd.h>
#include <utility>
#include <vector>

namespace gapchain {

using detail::SectionReader;
using nlohmann::json;

namespace {

/// json value of an override's text: JSON, else the text as a string; nan/inf are numbers.
/// key names the overridden key in the message on a duplicate key inside an object value.
json override_value(const std::string& key, const std::string& text) {
    if (spells_non_finite(text)) {
        // Only "nan" of the spellings has an a.
        if (text.find_first_of("aA") != std::string::npos)
            return std::numeric_limits<double>::quiet_NaN();
        return (text[0] == '-' ? -1.0 : 1.0) * std::numeric_limits<double>::infinity();
    }
    // A decimal number out of the doubles' range is held to the scene file's rule (1e999 was
    // taken as the string "1e999", 1e-999 as 0): the same message for the same fault.
    const std::string number_error = number_text_error(text);
    if (number_error.rfind("must be 0 or finite", 0) == 0)
        throw SceneError(key + ": a number " + number_error);
    // A whole number with a leading 0 (model.Nm=02, model.fc=010) is refused, as an integer flag
    // refuses it (read as decimal here, it would be octal to a shell's printf or to C), for a
    // real key too: --set does not know the key's type; 10 or 10.0 says what is meant.
    if (number_error.empty() && number_text_error(text, true).find("octal") != std::string::npos)
        throw SceneError(key + ": got \"" + text +
                         "\": a leading 0 would make it octal; write it without the 0 (or "
                         "as a decimal, 10.0)");
    json value = json::parse(text, nullptr, false);
    // A decimal that JSON does not spell (+5, .5, 5., 00.5) is a number all the same, as on the
    // command line.
    if (value.is_discarded() && number_error.empty())
        return json(std::strtod(text.c_str(), nullptr));
    if (value.is_discarded()) return json(text);
    // An array or object is held to the scene file's rules: a key given twice is refused, not
    // silently the last one; so are a number out of the doubles' range and deep nesting.
    if (value.is_structured()) return detail::parse_json_strictly<json>(text, "", key);
    return value;
}

/// "section.key=value" -> json[section][key] = value; deeper paths ("model.scatter.seed=3")
/// create or descend into nested objects.
void apply_override(json& root, const std::string& assignment) {
    const auto eq = assignment.find('=');
    const auto dot = assignment.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot > eq || dot == 0 ||
        dot + 1 == eq)
        throw SceneError("--set: expected section.key=value, got \"" + assignment + "\"");
    const std::string key = assignment.substr(0, eq);
    detail::set_scene_key(root, key, override_value(key, assignment.substr(eq + 1)),
                          "--set \"" + assignment + "\"");
}

std::vector<double> number_array(const json& j, const std::string& key) {
    // A --set value that is not JSON arrives as a string: "[NaN,0]" names a number JSON lacks.
    if (!j.is_array())
        throw SceneError(key + ": must be an array of finite numbers, got " +
                         detail::shown_json(j));
    std::vector<double> out;
    for (std::size_t i = 0; i < j.size(); ++i) {
        const json& x = j[i];
        const std::string entry = key + "[" + std::to_string(i) + "]";
        if (!x.is_number())
            throw SceneError(entry + ": must be a finite number, got " + detail::shown_json(x));
        const double v = x.get<double>();
        if (!std::isfinite(v))
            throw SceneError(entry + ": must be a finite number, got " +
                             std::string(std::isnan(v) ? "nan" : "inf"));
        out.push_back(v);
    }
    return out;
}

/// The per-body and per-gap arrays of a non-uniform row, in the scene's units.
struct RowArrays {
    std::vector<double> mass, stiffness, damping; ///< one per body
    std::vector<double> clearance, contact;       ///< one per gap, Nm + 1
};

/// model[key] as size numbers (fallback each when the key is absent); bodies names the
/// per-body size in the message.
std::vector<double> model_array(const json& model, const char* key, std::size_t size,
                                std::size_t bodies, double fallback) {
    std::vector<double> v(size, fallback);
    if (!model.contains(key)) return v;
    const std::string full = std::string("model.") + key;
    v = number_array(model[key], full);
    if (v.size() != size)
        throw SceneError(full + ": must have " + std::to_string(size) + " entries (" +
                         (size == bodies ? "one per body" : "one per gap, Nm + 1") + "), got " +
                         std::to_string(v.size()));
    return v;
}

/// model.scatter: every entry of an array times 1 + s N(0, 1), one random stream per array.
void apply_scatter(const json& scatter_json, RowArrays& a) {
    SectionReader scatter(scatter_json, "model.scatter",
                          {"clearance", "contact", "mass", "stiffness", "seed"});
    scatter.finish();
    const auto seed = static_cast<std::uint64_t>(scatter.integer("seed", 1, 0, 2'000'000'000));
    // A factor 1 + s z below its floor is refused, not clipped: at s = 5 half the draws were
    // set to the floor (clearances of exactly 0, masses of 0.001), which is no longer the
    // scatter the scene asks for.
    auto spread = [&](const char* key, std::vector<double>& v, std::uint64_t stream,
                      bool zero_allowed) {
        const double s = scatter.number(key, 0.0, 0.0, 10.0);
        for (std::size_t i = 0; i < v.size(); ++i) {
            const double factor = 1.0 + s * detail::standard_normal(seed, stream, i);
            if (factor < 0.0 || (factor == 0.0 && !zero_allowed))
                throw SceneError(
                    "model.scatter." + std::string(key) + ": s = " + detail::format_number(s) +
                    " draws the factor 1 + s z = " + detail::format_number(factor) + " for model." +
                    key + "[" + std::to_string(i) + "] (seed " + std::to_string(seed) +
                    "), which must stay " + (zero_allowed ? ">= 0" : "> 0") +
                    "; a smaller s (0.25 keeps it so to z = -4) or another seed");
            v[i] *= factor;
        }
    };
    // Clearances may close to zero; masses, stiffnesses and contacts must stay positive.
    spread("clearance", a.clearance, 1, true);
    spread("contact", a.contact, 2, false);
    spread("mass", a.mass, 3, false);
    spread("stiffness", a.stiffness, 4, false);
}

/// Throws SceneError on the first entry out of its range.
void check_row_arrays(const RowArrays& a) {
    auto check = [](const char* key, const std::vector<double>& v, double lo, bool open) {
        for (double x : v)
            if (!(open ? x > lo : x >= lo) || !std::isfinite(x))
                throw SceneError(std::string("model.") + key +
                                 ": every entry must be a finite number " + (open ? "> " : ">= ") +
                                 detail::format_number(lo) + ", got " + detail::format_number(x));
    };
    check("mass", a.mass, 0.0, true);
    check("stiffness", a.stiffness, 0.0, true);
    check("damping", a.damping, 0.0, false);
    check("clearance", a.clearance, 0.0, false);
    check("contact", a.contact, 0.0, true);
    // Relative masses and stiffnesses far from 1 would overflow the derived spring rates (the
    // message would then name a key the user never wrote).
    auto check_bounds = [](const char* key, const std::vector<double>& v, double lo, double hi) {
        for (double x : v)
            if (x < lo || x > hi)
                throw SceneError(std::string("model.") + key + ": every entry must be in [" +
                                 detail::format_number(lo) + ", " + detail::format_number(hi) +
                                 "], got " + detail::format_number(x));
    };
    check_bounds("mass", a.mass, 1e-6, 1e6);
    check_bounds("stiffness", a.stiffness, 1e-6, 1e6);
    check_bounds("damping", a.damping, 0.0, 100.0);
}

/// The row of p with the arrays' masses, stiffnesses, damping, clearances and contacts.
Chain row_from_arrays(const ReducedParameters& p, const RowArrays& a) {
    const auto n = static_cast<std::size_t>(p.Nm);
    Chain c = Chain::homogeneous(p);
    for (std::size_t i = 0; i < n; ++i) {
        c.mass[i] = a.mass[i];
        c.spring[i] = four_pi_squared * a.stiffness[i] / a.mass[i];
        c.damping[i] =
            4.0 * std::numbers::pi * a.damping[i] * std::sqrt(a.stiffness[i] / a.mass[i]);
    }
    for (std::size_t j = 0; j <= n; ++j) {
        c.clearance[j] = a.clearance[j];
        c.contact[j] *= a.contact[j];
    }
    return c;
}

/// A scalar the model's array replaces in every entry (e_r or e under model.clearance, eps
/// under model.damping) is refused: it was read, shown in the run's header and JSON, and never
/// used, so the output described a row other than the one that ran.
void refuse_replaced_scalar(const json& model, const char* array, const char* scalar) {
    if (model.contains(array) && model.contains(scalar))
        throw SceneError(std::string("model.") + scalar + ": not read where model." + array +
                         " gives every entry (the array replaces it); drop model." + scalar +
                         ", or change the array's entries");
}

/// The same key set twice would leave its value to the order of the arguments; so would a
/// key and a part of it (model.scatter={...} replaced an earlier model.scatter.seed=2).
void refuse_overlapping_overrides(const std::vector<std::string>& overrides) {
    for (std::size_t i = 0; i < overrides.size(); ++i)
        for (std::size_t k = 0; k < i; ++k) {
            const std::string key = overrides[i].substr(0, overrides[i].find('='));
            const std::string other = overrides[k].substr(0, overrides[k].find('='));
            const auto within = [](const std::string& part, const std::string& whole) {
                return part.size() > whole.size() && part.compare(0, whole.size(), whole) == 0 &&
                       part[whole.size()] == '.';
            };
            if (key == other)
                throw SceneError("--set " + key + ": given twice (\"" + overrides[k] + "\" and \"" +
                                 overrides[i] + "\")");
            if (within(key, other) || within(other, key))
                throw SceneError("--set " + key + ": overlaps --set " + other + " (\"" +
                                 overrides[k] + "\" and \"" + overrides[i] +
                                 "\"): set the part inside the whole, or the parts alone");
        }
}

/// A --set of model.clearance (model.damping) replaces the scene file's e_r or e (eps) in every
/// entry: the file's scalar is dropped, so that the shipped scenes, which all give e_r and eps,
/// take an array from the command line. A scalar given by --set too is still refused.
void drop_scalars_arrays_replace(json& root, const std::vector<std::string>& overrides) {
    if (!root.contains("model") || !root["model"].is_object()) return;
    json& model = root["model"];
    for (const auto& o : overrides) {
        std::string key;
        try {
            key = scene_key(o.substr(0, o.find('=')));
        } catch (const std::invalid_argument&) {
            continue; // apply_override() names the bad key in its own words
        }
        if (key == "model.clearance") {
            model.erase("e_r");
            model.erase("e");
        } else if (key == "model.damping") {
            model.erase("eps");
        }
    }
}

/// The row from the model's arrays and scatter, or nothing if the model gives neither.
// clearance_scale converts the scene's clearance entries to reduced clearances (1 for reduced
// scenes, 4 pi^2 f0^2 / a0 for metres); damping entries are eps_i (reduced scenes only).
// clearance_key is the scalar the clearance array replaces (e_r, or e in metres).
/// The model keys that make a row non-uniform (arrays, or a scatter of them).
constexpr const char* row_array_keys[] = {"mass",      "stiffness", "damping",
                                          "clearance", "contact",   "scatter"};

std::optional<Chain> non_uniform_row(const json& model, const ReducedParameters& p,
                                     const char* clearance_key = "e_r",
                                     double clearance_scale = 1.0) {
    if (!model.is_object()) return std::nullopt;
    refuse_replaced_scalar(model, "clearance", clearance_key);
    refuse_replaced_scalar(model, "damping", "eps");
    bool any = false;
    for (const char* k : row_array_keys)
        any = any || model.contains(k);
    if (!any) return std::nullopt;
    const auto n = static_cast<std::size_t>(p.Nm);
    RowArrays a;
    a.mass = model_array(model, "mass", n, n, 1.0);
    a.stiffness = model_array(model, "stiffness", n, n, 1.0);
    a.damping = model_array(model, "damping", n, n, p.eps);
    a.clearance = model_array(model, "clearance", n + 1, n, p.e_r / clearance_scale);
    for (double& e : a.clearance)
        e *= clearance_scale;
    a.contact = model_array(model, "contact", n + 1, n, 1.0);
    if (model.contains("scatter")) apply_scatter(model["scatter"], a);
    check_row_arrays(a);
    return row_from_arrays(p, a);
}

/// The scene's model section, or an empty object when it has none (a study's base scene may
/// leave the model to its parameters; const json's operator[] on a missing key is undefined).
const json& model_object(const json& root) {
    static const json empty = json::object();
    return root.contains("model") ? root.at("model") : empty;
}

/// The reduced model's five numbers (a reduced scene).
void read_reduced_model(SectionReader& model, SectionReader& excitation, Scene& scene) {
    model.allow({"Nm", "fc", "eps", "e_r", "mass", "stiffness", "damping", "clearance", "contact",
                 "scatter", "contact_law", "contact_damping"});
    excitation.allow({"f_r", "type"});
    ReducedParameters& p = scene.reduced;
    p.Nm = model.integer("Nm", p.Nm, 1, 1'000'000);
    p.fc = model.number("fc", p.fc, 0.0, 1e9, detail::Bound::open_low);
    p.eps = model.number("eps", p.eps, 0.0, 100.0);
    p.e_r = model.number("e_r", p.e_r, 0.0, 1e6);
    p.f_r = excitation.number("f_r", p.f_r, 0.0, 1e4, detail::Bound::open_low);
}

/// A recorded accelerogram (excitation.type = record); tail: seconds of free vibration after;
/// sets scene.record_file.
Accelerogram read_record_excitation(SectionReader& excitation, Scene& scene, double& tail) {
    excitation.allow({"file", "unit", "tail"});
    if (!excitation.has("file"))
        throw SceneError("excitation.file: required for excitation.type = record (a "
                         "two-column text/CSV file: time [s], acceleration)");
    const std::string file =
        detail::scene_relative_path(excitation.text("file", "", {}), scene.source);
    scene.record_file = file;
    const std::string unit = excitation.text("unit", "m/s2", {"m/s2", "g"});
    Accelerogram record = read_accelerogram(file, unit == "g" ? 9.80665 : 1.0);
    tail = excitation.number("tail", 0.0, 0.0, 1e5);
    return record;
}

/// A synthetic Kanai-Tajimi accelerogram (excitation.type = kanai_tajimi), unit PGA.
Accelerogram read_kanai_tajimi_excitation(SectionReader& excitation) {
    excitation.allow({"ground_frequency", "ground_damping", "duration", "sample_interval", "rise",
                      "hold", "decay", "seed"});
    KanaiTajimi kt;
    kt.ground_frequency = excitation.number("ground_frequency", kt.ground_frequency, 0.01, 100.0);
    kt.ground_damping = excitation.number("ground_damping", kt.ground_damping, 0.01, 5.0);
    kt.duration = excitation.number("duration", kt.duration, 0.1, 1e5);
    kt.sample_interval =
        excitation.number("sample_interval", kt.sample_interval, 0.0, 1.0, detail::Bound::open_low);
    kt.rise = excitation.number("rise", kt.rise, 0.0, 1e5);
    kt.hold = excitation.number("hold", kt.hold, 0.0, 1e5);
    kt.decay = excitation.number("decay", kt.decay, 0.0, 1e3);
    kt.seed = static_cast<std::uint64_t>(excitation.integer("seed", 1, 0, 2'000'000'000));
    return kanai_tajimi_accelerogram(kt, 1.0);
}

/// A record or synthetic ground motion of a physical scene: sets q.a0 (the PGA, or
/// excitation.a0 to scale to), q.f = f0 and the scene's ground record and its duration.
void read_ground_record(SectionReader& excitation, const std::string& type, Scene& scene,
                        PhysicalParameters& q) {
    // The reduced form takes the record's PGA as a0 and one natural period as the time loop's
    // unit (f = f0, so f_r = 1).
    double tail = 0.0;
    Accelerogram record = type == "record" ? read_record_excitation(excitation, scene, tail)
                                           : read_kanai_tajimi_excitation(excitation);
    scene.ground_motion_type = type;
    const double pga = peak_ground_acceleration(record);
    q.a0 = excitation.number("a0", pga, 0.0, 1e6, detail::Bound::open_low);
    for (double& a : record.acceleration)
        a *= q.a0 / pga;
    const double f0 = natural_frequency(q);
    q.f = f0;
    scene.ground_record = GroundMotion::from_accelerogram(record, f0, q.a0);
    scene.record_duration = record.time.back() + tail;
}

/// The physical model (SI units) and its ground motion, converted to reduced form.
void read_physical_model(SectionReader& model, SectionReader& excitation, const json& root,
                         const std::string& type, Scene& scene) {
    model.allow({"Nm", "M", "K", "C", "Kc", "e", "mass", "stiffness", "contact", "clearance",
                 "scatter", "contact_law"});
    excitation.allow({"a0", "type"});
    PhysicalParameters q;
    q.Nm = model.integer("Nm", q.Nm, 1, 1'000'000);
    q.M = model.number("M", q.M, 0.0, 1e12, detail::Bound::open_low);
    q.K = model.number("K", q.K, 0.0, 1e15, detail::Bound::open_low);
    q.C = model.number("C", q.C, 0.0, 1e15);
    q.Kc = model.number("Kc", q.Kc, 0.0, 1e18, detail::Bound::open_low);
    q.e = model.number("e", q.e, 0.0, 1e3);
    if (type == "harmonic") {
        excitation.allow({"f"});
        q.a0 = excitation.number("a0", q.a0, 0.0, 1e6, detail::Bound::open_low);
        q.f = excitation.number("f", q.f, 0.0, 1e6, detail::Bound::open_low);
    } else {
        read_ground_record(excitation, type, scene, q);
    }
    scene.physical = q;
    scene.reduced = to_reduced(q);
    if (model.text("contact_law", "linear", {}) != "linear")
        throw SceneError("model.contact_law: only \"linear\" in physical scenes (a nonlinear "
                         "law's stiffness unit depends on the law); write the scene in "
                         "reduced units");
    const double L = q.a0 / (four_pi_squared * natural_frequency(q) * natural_frequency(q));
    if (model_object(root).contains("damping"))
        throw SceneError("model.damping: per-body damping arrays are for reduced scenes "
                         "(eps_i); physical scenes give C");
    scene.row = non_uniform_row(model_object(root), scene.reduced, "e", 1.0 / L);
}

/// The row of a reduced scene: arrays, scatter and the contact law.
void read_reduced_row(SectionReader& model, const json& root, Scene& scene) {
    scene.row = non_uniform_row(model_object(root), scene.reduced);
    const std::string law =
        model.text("contact_law", "linear", {"linear", "hertz", "hunt_crossley"});
    if (law != "linear" && !scene.row) scene.row = Chain::homogeneous(scene.reduced);
    if (law == "hertz") scene.row->law = ContactLaw::hertz;
    if (law == "hunt_crossley") {
        scene.row->law = ContactLaw::hunt_crossley;
        scene.row->contact_damping = model.number("contact_damping", 0.0, 0.0, 1e6);
    } else if (model.has("contact_damping")) {
        throw SceneError("model.contact_damping: only with model.contact_law = hunt_crossley");
    }
}

/// run.periods and run.transient_periods ("auto" by default, MODEL.md §2); a record's run
/// covers the record and its tail.
void read_run_length(SectionReader& run, const std::string& type, Scene& scene) {
    RunOptions& o = scene.run;
    o.periods = run.integer("periods", 1000, 1, 1'000'000'000);
    if (run.has_text("transient_periods")) {
        if (run.text("transient_periods", "auto", {}) != "auto")
            throw SceneError(run.full("transient_periods") +
                             ": must be \"auto\" or an integer in [0, 999999999], got \"" +
                             run.text("transient_periods", "auto", {}) + "\"");
        o.transient_periods = auto_transient;
    } else {
        try {
            o.transient_periods = run.integer("transient_periods", auto_transient, 0, 999'999'999);
        } catch (const SceneError& e) { // the message names the other form too
            std::string m = e.what();
            const std::string integer = "must be an integer";
            if (const auto at = m.find(integer); at != std::string::npos)
                m.replace(at, integer.size(), "must be \"auto\" or an integer");
            throw SceneError(m);
        }
    }
    if (scene.ground_record) {
        if (run.has("periods") || run.has("transient_periods"))
            throw SceneError(std::string("run.") +
                             (run.has("periods") ? "periods" : "transient_periods") +
                             ": not used with excitation.type = " + type +
                             " (the record's length plus excitation.tail sets the run)");
        // A record has no periodic steady state to stop at: the keys were taken and ignored.
        for (const char* key : {"steady_state", "steady_tolerance", "max_steady_period"})
            if (run.has(key))
                throw SceneError(std::string("run.") + key +
                                 ": not used with excitation.type = " + type +
                                 " (the run covers the whole record and its tail; a transient "
                                 "excitation has no periodic steady state to stop at)");
        // The loop's unit is one natural period (reduced time 1); the run covers the record
        // and the tail.
        o.periods = std::max<long>(
            1, static_cast<long>(
                   std::ceil(scene.record_duration * natural_frequency(*scene.physical) - 1e-9)));
    }
    if (o.transient_periods != auto_transient && o.transient_periods >= o.periods)
        throw SceneError("run.transient_periods: must be \"auto\" or an integer in [0, "
                         "run.periods - 1 = " +
                         std::to_string(o.periods - 1) + "], got " +
                         std::to_string(o.transient_periods));
}

/// The keys of the run section (read_run() and the short keys of scene_key()).
const std::vector<std::string>& run_keys() {
    static const std::vector<std::string> keys{"periods",
                                               "transient_periods",
                                               "scheme",
                                               "tolerance",
                                               "step",
                                               "steady_state",
                                               "steady_tolerance",
                                               "max_steady_period",
                                               "estimate_error",
                                               "max_work",
                                               "multistability_check",
                                               "accuracy_mode"};
    return keys;
}

/// The run section: length, scheme, accuracy, steady-state stop, work limit.
void read_run(SectionReader run, const std::string& type, Scene& scene) {
    run.allow(run_keys());
    read_run_length(run, type, scene);
    RunOptions& o = scene.run;
    // The scheme names live in one place, parse_scheme(), whose message names run.scheme.
    o.scheme = parse_scheme(run.text("scheme", "auto", {}));
    o.tolerance = run.number("tolerance", o.tolerance, 1e-12, 0.1);
    if (run.has("step")) o.step = run.number("step", 0.0, 0.0, 1e3, detail::Bound::open_low);
    o.stop_at_steady_state = run.boolean("steady_state", o.stop_at_steady_state);
    o.steady_tolerance = run.number("steady_tolerance", o.steady_tolerance, 1e-15, 1e-2);
    o.max_steady_period = run.integer("max_steady_period", o.max_steady_period, 1, 1000);
    // Only the steady-state stop reads them (an attractor search refuses steady_state false):
    // accepted, they read as settings that took effect.
    for (const char* key : {"steady_tolerance", "max_steady_period"})
        if (!o.stop_at_steady_state && run.has(key))
            throw SceneError(std::string("run.") + key +
                             ": is read only with run.steady_state true; remove it, or set "
                             "run.steady_state true, got run.steady_state false");
    o.estimate_error = run.boolean("estimate_error", o.estimate_error);
    o.max_work = run.number("max_work", o.max_work, 1.0, 1e15);
    o.multistability_check = run.boolean("multistability_check", o.multistability_check);
    // The mode names live in parse_accuracy_mode(), whose message names run.accuracy_mode.
    o.accuracy_mode = parse_accuracy_mode(run.text("accuracy_mode", "auto", {"auto", "strict"}));
    run.finish();
}

/// One of initial.u, initial.v: Nm entries (zeros when absent), each within `limit` in the
/// scene's units, returned multiplied by `scale` (to reduced units).
std::vector<double> initial_entries(const json& initial, const std::string& key, std::size_t n,
                                    double limit, double scale, const std::string& unit) {
    const std::string name = "initial." + key;
    if (!initial.contains(key)) return std::vector<double>(n, 0.0);
    std::vector<double> x = number_array(initial[key], name);
    if (x.size() != n)
        throw SceneError(name + ": must have model.Nm = " + std::to_string(n) + " entries, got " +
                         std::to_string(x.size()));
    for (std::size_t i = 0; i < n; ++i) {
        if (std::abs(x[i]) > limit)
            throw SceneError(name + "[" + std::to_string(i) + "]: must be in [-" +
                             detail::format_number(limit) + ", " + detail::format_number(limit) +
                             "]" + unit + ", got " + detail::format_number(x[i]));
        x[i] *= scale;
    }
    return x;
}

/// initial.u and initial.v (Nm entries each; rest when absent): reduced, or in metres and
/// metres per second in a physical scene (MODEL.md §3, a0 the amplitude or a record's PGA:
/// u_r = 4 pi^2 f0^2 u / a0, and
/// v_r = du_r / dt_r = 4 pi^2 f0 v / a0). A reduced state beyond 1e9 has no physical meaning
/// (eq (20)'s amplitude is at most 1 / (2 eps) and the clearance at most 1e6) and its squares
/// near the double range would overflow silently.
void read_initial(const SectionReader& top, const json& root, Scene& scene) {
    if (!root.contains("initial")) return;
    SectionReader initial = top.section("initial");
    initial.allow({"u", "v"});
    initial.finish();
    const auto n = static_cast<std::size_t>(scene.reduced.Nm);
    constexpr double reduced_limit = 1e9;
    double u_scale = 1.0, v_scale = 1.0;
    std::string u_unit, v_unit;
    if (scene.physical) {
        // a0 is the harmonic amplitude or a record's peak (PGA): the reduction's unit either way.
        const double f0 = natural_frequency(*scene.physical);
        v_scale = four_pi_squared * f0 / scene.physical->a0;
        u_scale = v_scale * f0;
        u_unit = " m";
        v_unit = " m/s";
    }
    const json& ij = root["initial"];
    scene.initial = initial_entries(ij, "u", n, reduced_limit / u_scale, u_scale, u_unit);
    const std::vector<double> v =
        initial_entries(ij, "v", n, reduced_limit / v_scale, v_scale, v_unit);
    scene.initial.insert(scene.initial.end(), v.begin(), v.end());
}

Scene scene_from_json(json root, const std::vector<std::string>& overrides,
                      const std::string& source) {
    if (!root.is_object()) throw SceneError("scene: the top level must be a JSON object");
    // A tool's result JSON holds the scene it ran under "scene": a likely mix-up of files.
    if (root.contains("scene") && root.contains("F_m"))
        throw SceneError("scene: this file is a gapchain result (F_m, scene, ...), not a scene; "
                         "its \"scene\" key holds the scene it was computed from");
    refuse_overlapping_overrides(overrides);
    drop_scalars_arrays_replace(root, overrides);
    for (const auto& o : overrides)
        apply_override(root, o);
    SectionReader top(root, "", {"units", "model", "excitation", "run", "initial", "output"});
    Scene scene;
    scene.source = source;
    const std::string units = top.text("units", "reduced", {"reduced", "physical"});
    scene.units = units == "physical" ? Units::physical : Units::reduced;

    SectionReader model = top.section("model");
    SectionReader excitation = top.section("excitation");
    const std::string type =
        excitation.text("type", "harmonic", {"harmonic", "record", "kanai_tajimi"});
    if (type != "harmonic" && scene.units == Units::reduced)
        throw SceneError("excitation.type: " + type +
                         " needs \"units\": \"physical\" (a record's time and acceleration "
                         "carry units)");
    if (scene.units == Units::reduced) {
        read_reduced_model(model, excitation, scene);
        read_reduced_row(model, root, scene);
    } else {
        read_physical_model(model, excitation, root, type, scene);
    }
    scene.clearance_array = model_object(root).contains("clearance");
    scene.damping_array = model_object(root).contains("damping");
    if (scene.row) {
        for (const char* k : row_array_keys)
            if (model_object(root).contains(k))
                scene.non_uniform_keys +=
                    (scene.non_uniform_keys.empty() ? "model." : ", model.") + std::string(k);
        if (scene.row->law != ContactLaw::linear)
            scene.non_uniform_keys +=
                scene.non_uniform_keys.empty() ? "model.contact_law" : ", model.contact_law";
    }
    model.finish();
    excitation.finish();
    read_run(top.section("run"), type, scene);

    SectionReader output = top.section("output");
    output.allow({"trajectory_every"});
    scene.trajectory_every = output.integer("trajectory_every", 1, 1, 1'000'000);
    output.finish();
    read_initial(top, root, scene);
    top.finish();
    return scene;
}

} // namespace

Accelerogram read_accelerogram(const std::string& path, double unit) {
    std::ifstream in(path);
    if (!in) throw SceneError(path + ": cannot read the accelerogram file");
    Accelerogram record;
    std::string line;
    long number = 0;
    bool header_seen = false;
    while (std::getline(in, line)) {
        ++number;
        for (char& c : line)
            if (c == ',' || c == ';' || c == '\t' || c == '\r') c = ' ';
        const auto first = line.find_first_not_of(' ');
        if (first == std::string::npos || line[first] == '#') continue;
        std::istringstream fields(line);
        double t = 0.0, a = 0.0;
        std::string rest;
        const bool two = static_cast<bool>(fields >> t >> a);
        if (!two && record.time.empty() && !header_seen) {
            header_seen = true; // one line of column names
            continue;
        }
        if (!two || (fields >> rest) || !std::isfinite(t) || !std::isfinite(a))
            throw SceneError(path + ":" + std::to_string(number) +
                             ": expected two finite numbers (time [s], acceleration)");
        record.time.push_back(t);
        record.acceleration.push_back(a * unit);
    }
    if (in.bad()) throw SceneError(path + ": cannot read the accelerogram file");
    try {
        validate(record, path.c_str());
    } catch (const std::invalid_argument& e) {
        throw SceneError(e.what());
    }
    return record;
}

std::string scene_key(const std::string& key, const std::string& context) {
    // "model." and ".fc" name no key (Python's model.=1 was refused in --set's words).
    const auto dot = key.find('.');
    if (dot != std::string::npos && dot != 0 && key.back() != '.') return key;
    static const std::vector<std::pair<std::string, std::vector<std::string>>> sections = {
        {"model", {"Nm", "fc", "eps", "e_r"}},
        {"excitation", {"f_r"}},
        {"run", run_keys()},
        {"output", {"trajectory_every"}}};
    std::string list;
    for (const auto& [section, keys] : sections)
        for (const auto& k : keys) {
            if (k == key) return section + "." + key;
            list += (list.empty() ? "" : ", ") + k;
        }
    throw SceneError((context.empty() ? key : context) +
                     ": unknown key; a scene key is section.key (model.fc, excitation.f_r, "
                     "run.periods, ...) or one of the short keys " +
                     list);
}

bool key_unread_by_modes(const std::string& dotted_key) {
    // The linear chain has no clearance (e_r = 0) and its modes are undamped: model.eps = 7 and
    // model.clearance were taken, and the modes printed unchanged.
    static const std::array<const char*, 8> model_keys{
        "model.eps", "model.C",         "model.damping",         "model.e_r",
        "model.e",   "model.clearance", "model.contact_damping", "model.scatter.clearance"};
    return dotted_key.rfind("excitation.", 0) == 0 || dotted_key.rfind("initial.", 0) == 0 ||
           std::find(model_keys.begin(), model_keys.end(), dotted_key) != model_keys.end();
}

std::array<std::string, 2> keys_replaced_by(SweptParameter which) {
    // f_r = f / f0, e_r = (2 pi f0)^2 e / a0, fc = Kc / K, eps = C / (2 sqrt(K M)): of the
    // physical keys, f, e, Kc and C each enter one reduced number only.
    switch (which) {
    case SweptParameter::f_r: return {"excitation.f_r", "excitation.f"};
    case SweptParameter::e_r: return {"model.e_r", "model.e"};
    case SweptParameter::fc: return {"model.fc", "model.Kc"};
    case SweptParameter::eps: return {"model.eps", "model.C"};
    }
    throw std::invalid_argument("keys_replaced_by: unknown parameter");
}

Scene parse_scene(std::string_view text, const std::vector<std::string>& overrides,
                  const std::string& source) {
    return detail::scene_from_parsed_json(detail::parse_json_strictly<json>(text, source),
                                          overrides, source);
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
    return parse_scene(detail::read_text_file(path, "scene"), overrides, path);
}

namespace detail {

void JsonKeyTrail::open(bool object) {
    m_containers.push_back(object);
    if (!object) return;
    const std::string parent =
        m_levels.empty() ? std::string() : m_levels.back().path + m_levels.back().last_key + ".";
    m_levels.push_back({{}, parent, {}});
}

void JsonKeyTrail::close(bool object) {
    if (!m_containers.empty()) m_containers.pop_back();
    if (object && !m_levels.empty()) m_levels.pop_back();
}

void JsonKeyTrail::key(const std::string& name) {
    if (m_levels.empty()) return;
    if (!m_levels.back().keys.insert(name).second)
        throw error_at(m_levels.back().path + name, "duplicate key (given twice in one object; "
                                                    "JSON keeps only one, so the scene is "
                                                    "ambiguous)");
    m_levels.back().last_key = name;
}

SceneError JsonKeyTrail::error_at(const std::string& key, const std::string& rule) const {
    const std::string path =
        m_within.empty() || key.empty() ? m_within + key : m_within + "." + key;
    return SceneError((m_source.empty() ? std::string() : m_source + ": ") +
                      (path.empty() ? std::string() : path + ": ") + rule);
}

SceneError JsonKeyTrail::value_error(const std::string& rule) const {
    return error_at(
        m_levels.empty() ? std::string() : m_levels.back().path + m_levels.back().last_key, rule);
}

std::optional<UnreadableNumber> first_unreadable_number(std::string_view text) {
    std::size_t ordinal = 0;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '"') {
            // A string: skip to its closing quote, past escaped ones.
            for (++i; i < text.size() && text[i] != '"'; ++i)
                if (text[i] == '\\') ++i;
            continue;
        }
        if (c != '-' && (c < '0' || c > '9')) continue;
        std::size_t end = i;
        while (end < text.size() && std::strchr("+-0123456789.eE", text[end]) && text[end] != 0)
            ++end;
        const std::string number(text.substr(i, end - i));
        ++ordinal;
        i = end - 1;
        if (const std::string error = number_text_error(number); !error.empty())
            return UnreadableNumber{ordinal, "a number " + error};
    }
    return std::nullopt;
}

std::string non_finite_literal_at(std::string_view text, std::size_t last_read, bool in_object) {
    if (last_read == 0 || last_read > text.size()) return {};
    const auto is_letter = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; };
    std::size_t begin = last_read - 1;
    while (begin > 0 && is_letter(text[begin - 1]))
        --begin;
    if (begin > 0 && text[begin - 1] == '-') --begin;
    std::size_t end = begin + (text[begin] == '-' ? 1 : 0);
    while (end < text.size() && is_letter(text[end]))
        ++end;
    std::string literal(text.substr(begin, end - begin));
    if (!spells_non_finite(literal)) return {};
    std::size_t before = begin;
    while (before > 0 && std::isspace(static_cast<unsigned char>(text[before - 1])))
        --before;
    if (before == 0 || std::strchr(in_object ? ":" : "[,", text[before - 1]) == nullptr) return {};
    return literal;
}

std::string scene_relative_path(const std::string& path, const std::string& source) {
    const std::filesystem::path file = path;
    if (file.is_relative() && !source.empty() && source.front() != '<')
        return (std::filesystem::path(source).parent_path() / file).string();
    return path;
}

std::string read_text_file(const std::string& path, const std::string& what) {
    std::error_code ec;
    if (path.empty()) throw SceneError(what + " file: empty path");
    // open() would read the path up to the NUL: Python's "fig5.json\0junk" ran fig5.json.
    if (path.find('\0') != std::string::npos)
        throw SceneError(what + " file: the path holds a NUL byte, got \"" + visible(path) + "\"");
    if (std::filesystem::is_directory(path, ec))
        throw SceneError(path + ": is a directory, not a " + what + " file");
    // A device (a terminal, /dev/zero) would block or never end.
    const auto type = std::filesystem::status(path, ec).type();
    if (type == std::filesystem::file_type::socket ||
        type == std::filesystem::file_type::character || type == std::filesystem::file_type::block)
        throw SceneError(path + ": is a socket or device, not a " + what + " file");
    // A pipe is read (`gapchain-sim <(jq ... scene.json)`), but opened without waiting: a named
    // pipe no one writes to blocked open() until a writer came, and the first Ctrl-C only sets
    // the tools' interrupt flag. Once open, reads wait as usual; with no writer they end at once.
    errno = 0;
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0 || ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK) < 0) {
        const int reason = errno;
        if (fd >= 0) ::close(fd);
        throw SceneError(path + ": cannot read the " + what +
                         " file: " + (reason ? std::strerror(reason) : "unreadable"));
    }
    const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(::fdopen(fd, "rb"), &std::fclose);
    if (!file) {
        ::close(fd);
        throw SceneError(path + ": cannot read the " + what + " file: " + std::strerror(errno));
    }
    // stdio, not a stream's rdbuf(): a read error there only failed the copy, which an empty
    // file fails too, so /proc/self/mem was reported as malformed JSON. A scene is kilobytes:
    // 64 MiB bounds what an endless pipe can take.
    constexpr std::size_t largest = std::size_t{64} << 20;
    std::string text;
    char buffer[1 << 16];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, file.get())) > 0) {
        text.append(buffer, n);
        if (text.size() > largest)
            throw SceneError(path + ": longer than 64 MiB: not a " + what + " file");
    }
    if (std::ferror(file.get()))
        throw SceneError(path + ": cannot read the " + what +
                         " file: " + (errno ? std::strerror(errno) : "read error"));
    if (text.empty() && type == std::filesystem::file_type::fifo)
        throw SceneError(path + ": a pipe with nothing written to it; give a " + what + " file");
    // The JSON reader stops at a NUL: what follows it would be dropped without a word.
    if (const auto nul = text.find('\0'); nul != std::string::npos)
        throw SceneError(path + ": a NUL byte at offset " + std::to_string(nul) + ": not a text " +
                         what + " file");
    return text;
}

} // namespace detail

namespace detail {

void set_scene_key(json& root, const std::string& path, json value, const std::string& context) {
    // Every dotted part before the last names an object, created when missing.
    const auto last_dot = path.rfind('.');
    const std::string key = path.substr(last_dot == std::string::npos ? 0 : last_dot + 1);
    if (last_dot == std::string::npos)
        throw SceneError(context + ": unknown key; a scene key is section.key (model.fc, "
                                   "excitation.f_r, run.periods, ...)");
    if (key.empty()) throw SceneError(context + ": expected section.key, got \"" + path + "\"");
    // "initial.u[0]" would be read as an unknown key named "u[0]", next to a list naming u.
    if (const auto bracket = path.find('['); bracket != std::string::npos)
        throw SceneError(context + ": a key cannot index into an array; give the whole array (" +
                         path.substr(0, bracket) + "=[...])");
    json* parent = &root;
    for (std::size_t start = 0; start <= last_dot;) {
        const auto end = path.find('.', start);
        const std::string part = path.substr(start, end - start);
        if (part.empty()) throw SceneError(context + ": empty key in \"" + path + "\"");
        if (!parent->contains(part)) (*parent)[part] = json::object();
        if (!(*parent)[part].is_object())
            throw SceneError(path.substr(0, end) + ": must be an object to set " +
                             path.substr(end + 1));
        parent = &(*parent)[part];
        start = end + 1;
    }
    (*parent)[key] = std::move(value);
}

Scene scene_from_parsed_json(json root, const std::vector<std::string>& overrides,
                             const std::string& source) {
    try {
        return scene_from_json(std::move(root), overrides, source);
    } catch (const SceneError&) {
        throw;
    } catch (const std::invalid_argument& e) {
        throw SceneError(e.what());
    }
}

} // namespace detail

void require_paper_row(const Scene& scene, const std::string& user) {
    if (!scene.harmonic())
        throw SceneError("excitation.type: " + user +
                         " needs harmonic forcing (a forcing period); records and Kanai-Tajimi "
                         "motion work in gapchain-sim and gapchain-sweep");
    if (!scene.uniform()) {
        const bool law = scene.row && scene.row->law != ContactLaw::linear;
        // The keys the scene wrote (model.clearance, model.scatter), not a label for them.
        throw SceneError(
            (scene.non_uniform_keys.empty() ? std::string("model") : scene.non_uniform_keys) +
            ": " + user +
            " takes the paper's uniform row with the linear law (Nm, "
            "fc, eps, e_r, f_r); " +
            (law ? "nonlinear laws work in gapchain-sim, -sweep, -poincare and "
                   "-spectrum"
                 : "non-uniform rows work in gapchain-sim, -poincare, -spectrum, "
                   "-modes, -orbit and -accuracy"));
    }
}

std::string number_text_error(std::string_view text, bool integer) {
    // A scanner, not std::regex: libstdc++'s regex recurses once per character, and a flag of
    // 50,000 digits overflowed the stack.
    std::size_t i = text.empty() || (text[0] != '+' && text[0] != '-') ? 0 : 1;
    const auto digits = [&] {
        const std::size_t first = i;
        while (i < text.size() && text[i] >= '0' && text[i] <= '9')
            ++i;
        return i - first;
    };
    const std::size_t whole_from = i;
    std::size_t mantissa = digits();
    bool plain = true;
    if (integer) {
        plain = mantissa > 0 && !(mantissa > 1 && text[whole_from] == '0');
    } else {
        if (i < text.size() && text[i] == '.') {
            ++i;
            mantissa += digits();
        }
        plain = mantissa > 0;
        if (plain && i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
            ++i;
            if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
            plain = digits() > 0;
        }
    }
    const std::string shown =
        "\"" + std::string(text.size() > 60 ? std::string(text.substr(0, 57)) + "..." : text) +
        "\"";
    if (!plain || i != text.size()) {
        const std::string_view unsigned_text = text.substr(whole_from);
        const bool hex = unsigned_text.size() > 1 && unsigned_text[0] == '0' &&
                         (unsigned_text[1] == 'x' || unsigned_text[1] == 'X');
        const bool octal = integer && mantissa > 1 && i == text.size() && text[whole_from] == '0';
        return std::string(integer ? "must be a decimal integer"
                                   : "must be a finite decimal number") +
               ", got " + shown +
               (hex     ? " (hex is not read)"
                : octal ? " (a leading 0 would make it octal)"
                        : "");
    }
    const std::string number(text);
    const double x = std::strtod(number.c_str(), nullptr);
    const bool written_nonzero =
        number.substr(0, number.find_first_of("eE")).find_first_of("123456789") !=
        std::string::npos;
    if (!std::isfinite(x) || (written_nonzero && std::abs(x) < DBL_MIN))
        return "must be 0 or finite with |x| in [2.2250738585072014e-308, "
               "1.7976931348623157e308] (the normal doubles), got " +
               shown;
    return {};
}

bool spells_non_finite(std::string_view text) {
    if (!text.empty() && (text[0] == '+' || text[0] == '-')) text.remove_prefix(1);
    std::string lower;
    for (const char c : text)
        lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return lower == "nan" || lower == "inf" || lower == "infinity";
}

void require_linear_harmonic(const Scene& scene, const std::string& user, const std::string& why) {
    if (!scene.harmonic())
        throw SceneError("excitation.type: " + user + " needs harmonic forcing (" + why +
                         "); records and Kanai-Tajimi motion work in gapchain-sim and "
                         "gapchain-sweep");
    if (scene.row && scene.row->law != ContactLaw::linear)
        throw SceneError("model.contact_law: " + user + " needs the linear contact law (" + why +
                         "), got " + to_string(scene.row->law) +
                         "; nonlinear laws work in gapchain-sim, -sweep, -poincare and -spectrum");
}

} // namespace gapchain
