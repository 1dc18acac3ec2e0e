// gapchain.classify, regime_map and sweep: regimes of points and maps, parametric studies.
#include "call.hpp"

#include "gapchain/classify.hpp"
#include "gapchain/design_value.hpp"
#include "gapchain/report.hpp"
#include "gapchain/study.hpp"

#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

namespace gapchain::python {

namespace {

/// An error nothing estimated (infinite: too few periods averaged) as NaN, as the arrays and
/// a sweep's columns write it (JSON null, an empty CSV field).
double estimated_or_nan(double error) {
    return std::isfinite(error) ? error : std::numeric_limits<double>::quiet_NaN();
}

constexpr const char* classify_doc =
    R"(classify(scene=None, *, transient=100, record=300, confirm=True, twin=True, attractors=0, seed=None, box=None, threads=None, **keys) -> dict

Classify the paper's uniform row at one point as "no-contact", "periodic" (with its period),
"quasi-periodic" or "chaotic", with the evidence: gapchain-classify in-process.

transient  settling periods (ended early by a periodic steady state), >= 0
record     periods of evidence for non-periodic motion, >= 20
confirm    confirm a periodic regime by Newton shooting (period = the orbit's minimal period)
twin       on a quasi-periodic or chaotic label, classify again from a start moved by 1e-8
          (doubles such a point's cost): start_dependent says whether the label or F_m moved
attractors also search the row's attractors from this many random starts, 0 .. 1e7, each run
          as long as the classification's (seed, box, threads as in simulate()), and set the
          label against them: adds multistable, label_in_search ("attractor": a settled
          chaotic or quasi-periodic group has the label's F_m; "transient": only an unsettled
          one, as on Fig 13's row at f_r = 2.05, a chaotic saddle; "not_reached": none, no
          verdict; None for a periodic label) and design_value, as gapchain-classify
          --attractors N
scene, **keys  the row (Nm, fc, eps, e_r, f_r; of the run section scheme, tolerance and
          max_work are used) and its initial state.

Returns a dict: regime, period (forcing periods; 0 if not periodic or longer than 16),
lambda_max (largest Lyapunov exponent per unit reduced time; a Newton-confirmed orbit's
from its largest multiplier, error 0; an unconfirmed periodic label's averaged over at least
20 periods of the orbit, restarted at the settle) and lambda_max_error (None where too few
periods were averaged for it),
distinct_points, section_points, broadband_share ([0, 1]; 0 where the run settled) and
broadband_share_error (its Welch segments' spread plus the aliased share; None where the
record was too short to read it), F_m (a Newton-confirmed orbit's,
else the record's maximum), F_m_error (tolerance * F_m on a periodic state, else the recorded
halves' spread, at least that; covering the record's maximum too), stopped_at_steady_state,
start_up_periods and start_up_in_record (on a quasi-periodic or chaotic label: the periods the
contact-free start-up takes to decay, and whether that exceeds the discarded ones, so that the
record may be the start-up's; raise transient), settled_in_record (the state settled on a
periodic steady state while recording: the label and F_m are its, the bar covers the record's
maximum before), twin_checked, twin (where one ran: regime, period, F_m, F_m_error, lambda_max,
lambda_max_error, newton_confirmed, settled_in_record, status of the classification from a
start moved by 1e-8), start_dependent (None where no twin ran its course; True where the twin's
label differs or its F_m lies beyond 3 error bars: F_m_error covers the difference, and
lambda_max_error too where the labels agree; False is "not detected"), newton_confirmed, max_multiplier (0 unless confirmed), periods_run, scheme (the one the run
took: "exact" where the Lyapunov spectrum takes it), status, wall_time_s, parameters.)";

constexpr const char* regime_map_doc =
    R"(regime_map(scene=None, *, e_r, f_r, transient=100, record=300, confirm=True, twin=True, threads=0, progress=None, **keys) -> dict

Classify every (e_r, f_r) of a grid around the scene's row, in parallel (Fig 2 of the paper):
gapchain-classify --map in-process. Results do not depend on the thread count.

e_r, f_r   the row and column values: sequences of numbers (e.g. numpy.linspace(0, 1.5, 30))
threads    OpenMP threads (0: all cores);  progress  callable(fraction of cells done)
transient, record, confirm, twin  as in classify().

Returns a dict: e_r ((rows,)), f_r ((cols,)), and (rows x cols) arrays regime (str), code
(0 no-contact, 1 periodic, 2 quasi-periodic, 3 chaotic), period, F_m, F_m_error, lambda_max,
lambda_max_error (NaN where not estimated), distinct_points, broadband_share,
broadband_share_error (NaN where not estimated), twin_checked, start_dependent (False also
where no twin ran), settled_in_record, status;
wall_time_s, threads_used,
cancelled (an interrupted call, by KeyboardInterrupt or an exception progress raises, sets what it had done, cancelled true, as the exception's partial).)";

constexpr const char* sweep_doc = R"(sweep(study, *, threads=0, progress=None) -> dict

Run a parametric study (docs/sweep.md): a base scene, axes of values for scene keys and a
sampling of their product; every point simulated (and classified if the study keeps
"regime"), in parallel: gapchain-sweep in-process, without the results file.

study     a study dict ({"scene": {...}, "parameters": {"fc": [1, 10], "e_r": {"lin":
          [0, 1.5, 61]}}, "sample": ..., "keep": [...]}) or the path of a study file; at
          most 1e6 points (every row is kept until the call returns; gapchain-sweep streams)
threads   OpenMP threads (0: all cores);  progress  callable(fraction of points done)

Returns a dict of columns in index order: index, one column per axis (named by its key), Nm,
fc, eps, e_r, f_r, F_m, F_m_error (NaN: not estimated), status, multistable (bool;
False also where run.multistability_check was false, which the CSV leaves empty),
steady_state_period (0: none), longer_cycle_period (0: none; the cycle of a point that did
not settle within run.max_steady_period), wall_time_s; with "per_body" kept, per_body (points x Nm x 2; a study over model.Nm pads shorter rows with
NaN to the largest Nm) and per_body_error (the same shape; NaN where not estimated); with "regime" kept, regime,
period, lambda_max, lambda_max_error, regime_start_dependent (bool; False also where no twin
ran, which the CSV leaves empty), regime_settled_in_record (bool: the transient ended while
recording, the label is the steady state's); with "F_m_orbit" kept, F_m_orbit (NaN: did not settle),
F_m_orbit_error (NaN: not estimated) and maximum_in_transient (bool; False also where the run settled on no orbit, which the CSV
leaves empty); with "attractors", F_m_max, F_m_max_error (NaN: not
estimated), attractors and unsettled; F_m_newton and F_m_error_newton (NaN: not estimated) for
physical scenes (and F_m_max_newton, F_m_max_error_newton with "attractors"); and cancelled (an interrupted call, by KeyboardInterrupt or an exception progress raises, sets what it had done, cancelled true, as the exception's partial).)";

// How classify() and regime_map() run, for the refusal of a run key they do not read.
const std::string classify_runs = "it runs transient, then record periods";
// The run key a library message advises to change, and the keywords that change it here.
const std::pair<std::string, std::string> classify_lengths{"run.periods", "transient, record"};

ClassifyOptions classify_options(const Scene& scene, long transient, long record, bool confirm,
                                 bool twin) {
    ClassifyOptions o;
    o.transient_periods = transient;
    o.record_periods = record;
    o.confirm_by_newton = confirm;
    o.twin_check = twin;
    take_run_settings(scene, o);
    validate(o);
    return o;
}

py::dict classify_py(const py::object& scene_arg, long transient, long record, bool confirm,
                     bool twin, long attractors, std::optional<std::uint64_t> seed,
                     std::optional<double> box, std::optional<int> threads,
                     const py::kwargs& keys) {
    refuse_run_keys(keys, "classify", run_settings_keys, classify_runs);
    const Scene scene = to_scene(scene_arg, keys);
    ClassifyOptions o = classify_options(scene, transient, record, confirm, twin);
    // The label is set against the search's groups by their section points too.
    o.keep_section_states = attractors != 0;
    Call call;
    const ReducedParameters& row = paper_row(scene, "classify");
    Classification c;
    const std::string json =
        advising_keywords(classify_lengths.first, classify_lengths.second, [&] {
            // Each start of the search runs as long as the classification (gapchain-classify's).
            const AttractorOptions search = design_search(scene, classify_search_run(o), "classify",
                                                          attractors, seed, box, threads);
            c = call.run([&] { return classify(row, o, call.callback()); });
            if (attractors == 0 || c.status == RunStatus::cancelled) return to_json(c, o, row);
            const DesignValue design =
                call.run([&] { return design_value(row, search, c, call.callback()); });
            return to_json(c, o, scene, design, search);
        });
    // The JSON gapchain-classify writes (report.cpp, the one list of the fields), as a dict; an
    // error nothing estimated (too few periods averaged) stays None, as the JSON's null.
    py::dict d = py::module_::import("json").attr("loads")(json);
    d["max_multiplier"] = c.max_multiplier;
    return d;
}

// A field of every cell as a rows x cols array.
template <class R, class F>
py::array grid(const RegimeMap& m, F field) {
    return column<R>(m.cells, field).attr("reshape")(m.e_r.size(), m.f_r.size());
}

py::dict regime_map_dict(const RegimeMap& m) {
    using C = Classification;
    // A cell an interrupted map did not run (status cancelled) is no classification: not
    // "no-contact" with F_m 0, as the cell's defaults read (the CSV leaves such cells out).
    const auto ran = [](const C& c) { return c.status != RunStatus::cancelled; };
    const auto number = [&ran](double (*field)(const C&)) {
        return [&ran, field](const C& c) {
            return ran(c) ? field(c) : std::numeric_limits<double>::quiet_NaN();
        };
    };
    py::dict d;
    d["e_r"] = array(m.e_r);
    d["f_r"] = array(m.f_r);
    d["regime"] = strings(m.cells, [&ran](const C& c) {
                      return ran(c) ? to_string(c.regime) : std::string_view("not run");
                  }).attr("reshape")(m.e_r.size(), m.f_r.size());
    d["code"] =
        grid<int>(m, [&ran](const C& c) { return ran(c) ? static_cast<int>(c.regime) : -1; });
    d["period"] = grid<int>(m, [&ran](const C& c) { return ran(c) ? c.period : -1; });
    d["F_m"] = grid<double>(m, number([](const C& c) { return c.F_m; }));
    d["F_m_error"] = grid<double>(m, number([](const C& c) { return c.F_m_error; }));
    d["lambda_max"] = grid<double>(m, number([](const C& c) { return c.lambda_max; }));
    d["lambda_max_error"] =
        grid<double>(m, number([](const C& c) { return estimated_or_nan(c.lambda_max_error); }));
    d["distinct_points"] =
        grid<int>(m, [&ran](const C& c) { return ran(c) ? c.distinct_points : -1; });
    d["broadband_share"] = grid<double>(m, number([](const C& c) { return c.broadband_share; }));
    d["broadband_share_error"] =
        grid<double>(m, number([](const C& c) { return c.broadband_share_error; }));
    d["twin_checked"] = grid<bool>(m, [](const C& c) { return c.twin_checked; });
    d["start_dependent"] = grid<bool>(m, [](const C& c) { return c.start_dependent; });
    d["settled_in_record"] = grid<bool>(m, [](const C& c) { return c.settled_in_record; });
    d["status"] = strings(m.cells, [](const C& c) {
                      return to_string(c.status);
                  }).attr("reshape")(m.e_r.size(), m.f_r.size());
    d["wall_time_s"] = m.wall_time_s;
    d["threads_used"] = m.threads_used;
    d["cancelled"] = m.cancelled;
    return d;
}

py::dict regime_map_py(const py::object& scene_arg, const std::vector<double>& e_r,
                       const std::vector<double>& f_r, long transient, long record, bool confirm,
                       bool twin, int threads, const py::object& progress, const py::kwargs& keys) {
    refuse_run_keys(keys, "regime_map", run_settings_keys, classify_runs);
    for (const char* axis : {"e_r", "f_r"})
        refuse_swept_keys(keys, axis, "regime_map", std::string("over its ") + axis + " argument");
    const Scene scene = to_scene(scene_arg, keys);
    const ClassifyOptions o = classify_options(scene, transient, record, confirm, twin);
    Call call(progress);
    const ReducedParameters& row = paper_row(scene, "regime_map");
    try {
        return advising_keywords(classify_lengths.first, classify_lengths.second, [&] {
            return call.run([&] { return regime_map(row, e_r, f_r, o, threads, call.callback()); },
                            regime_map_dict);
        });
    } catch (const std::invalid_argument& e) {
        // The scene loaded, so a value the row refuses is one of the lists': named as the
        // argument ("model.e_r: ..." read as the scene's key).
        const std::string message = e.what();
        for (const auto& [key, argument] :
             {std::pair{"model.e_r:", "e_r:"}, std::pair{"excitation.f_r:", "f_r:"}})
            if (message.rfind(key, 0) == 0)
                throw std::invalid_argument(argument + message.substr(std::strlen(key)));
        throw;
    }
}

void axis_columns(py::dict& d, const Study& study, const std::vector<SweepPointResult>& rows) {
    using R = SweepPointResult;
    for (std::size_t a = 0; a < study.axes.size(); ++a)
        d[py::str(study.axes[a].key)] =
            column<double>(rows, [a](const R& r) { return r.values[a]; });
    d["Nm"] = column<int>(rows, [](const R& r) { return r.parameters.Nm; });
    d["fc"] = column<double>(rows, [](const R& r) { return r.parameters.fc; });
    d["eps"] = column<double>(rows, [](const R& r) { return r.parameters.eps; });
    d["e_r"] = column<double>(rows, [](const R& r) { return r.parameters.e_r; });
    d["f_r"] = column<double>(rows, [](const R& r) {
        return r.harmonic ? r.parameters.f_r : std::numeric_limits<double>::quiet_NaN();
    });
}

/// per_body and per_body_error, points x Nm x 2.
void per_body_columns(py::dict& d, const std::vector<SweepPointResult>& rows) {
    // Rows of a study over model.Nm differ in length: each is padded to the longest with
    // NaN (they were read past their end, from the first row's length).
    std::size_t n = 0;
    for (const auto& r : rows)
        n = std::max(n, r.simulation.per_body.size());
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> forces(rows.size() * n * 2, nan), errors(forces.size(), nan);
    for (std::size_t k = 0; k < rows.size(); ++k)
        for (std::size_t i = 0; i < rows[k].simulation.per_body.size(); ++i) {
            const BodyMaximum& b = rows[k].simulation.per_body[i];
            const std::size_t at = (k * n + i) * 2;
            forces[at] = b.left;
            forces[at + 1] = b.right;
            // NaN where no comparison run estimated them (as F_m_error's column).
            errors[at] = b.left_error;
            errors[at + 1] = b.right_error;
        }
    d["per_body"] = matrix(forces, rows.size(), n * 2).attr("reshape")(rows.size(), n, 2);
    d["per_body_error"] = matrix(errors, rows.size(), n * 2).attr("reshape")(rows.size(), n, 2);
}

void kept_columns(py::dict& d, const Study& study, const std::vector<SweepPointResult>& rows) {
    using R = SweepPointResult;
    if (study.keep.per_body) per_body_columns(d, rows);
    if (study.keep.regime) {
        d["regime"] = strings(rows, [](const R& r) { return to_string(r.regime->regime); });
        d["period"] = column<int>(rows, [](const R& r) { return r.regime->period; });
        d["lambda_max"] = column<double>(rows, [](const R& r) { return r.regime->lambda_max; });
        d["lambda_max_error"] = column<double>(
            rows, [](const R& r) { return estimated_or_nan(r.regime->lambda_max_error); });
        d["regime_start_dependent"] =
            column<bool>(rows, [](const R& r) { return r.regime->start_dependent; });
        d["regime_settled_in_record"] =
            column<bool>(rows, [](const R& r) { return r.regime->settled_in_record; });
    }
    if (study.keep.orbit) {
        d["F_m_orbit"] = column<double>(rows, [](const R& r) {
            return r.simulation.F_m_orbit.value_or(std::numeric_limits<double>::quiet_NaN());
        });
        d["F_m_orbit_error"] = column<double>(rows, [](const R& r) {
            return r.simulation.F_m_orbit_error.value_or(std::numeric_limits<double>::quiet_NaN());
        });
        d["maximum_in_transient"] =
            column<bool>(rows, [](const R& r) { return r.simulation.maximum_in_transient; });
    }
    if (study.attractor_starts > 0) {
        d["F_m_max"] =
            column<double>(rows, [](const R& r) { return r.F_m_max.value_or(r.simulation.F_m); });
        d["F_m_max_error"] = column<double>(rows, [](const R& r) {
            if (r.F_m_max) return r.F_m_max_error;
            return has_error_estimate(r.simulation) ? r.simulation.F_m_error
                                                    : std::numeric_limits<double>::quiet_NaN();
        });
        d["attractors"] = column<int>(rows, [](const R& r) { return r.attractors_found; });
        d["unsettled"] = column<int>(rows, [](const R& r) { return r.attractors_unsettled; });
    }
    if (!rows.empty() && rows.front().F_m_newton) {
        d["F_m_newton"] = column<double>(rows, [](const R& r) { return *r.F_m_newton; });
        d["F_m_error_newton"] = column<double>(rows, [](const R& r) {
            return r.F_m_error_newton.value_or(std::numeric_limits<double>::quiet_NaN());
        });
        if (study.attractor_starts > 0) {
            d["F_m_max_newton"] = column<double>(rows, [](const R& r) {
                return r.F_m_max_newton.value_or(std::numeric_limits<double>::quiet_NaN());
            });
            d["F_m_max_error_newton"] = column<double>(rows, [](const R& r) {
                return r.F_m_max_error_newton.value_or(std::numeric_limits<double>::quiet_NaN());
            });
        }
    }
}

py::dict sweep_dict(const Study& study, std::vector<SweepPointResult> rows) {
    using R = SweepPointResult;
    std::sort(rows.begin(), rows.end(), [](const R& a, const R& b) { return a.index < b.index; });
    py::dict d;
    d["index"] = column<long>(rows, [](const R& r) { return r.index; });
    axis_columns(d, study, rows);
    d["F_m"] = column<double>(rows, [](const R& r) { return r.simulation.F_m; });
    d["F_m_error"] = column<double>(rows, [](const R& r) {
        return has_error_estimate(r.simulation) ? r.simulation.F_m_error
                                                : std::numeric_limits<double>::quiet_NaN();
    });
    d["status"] = strings(rows, [](const R& r) { return to_string(r.simulation.status); });
    d["multistable"] = column<bool>(rows, [](const R& r) { return r.multistable; });
    d["steady_state_period"] =
        column<int>(rows, [](const R& r) { return r.simulation.steady_state_period.value_or(0); });
    d["longer_cycle_period"] =
        column<int>(rows, [](const R& r) { return r.simulation.longer_cycle_period.value_or(0); });
    d["wall_time_s"] = column<double>(rows, [](const R& r) { return r.simulation.wall_time_s; });
    kept_columns(d, study, rows);
    return d;
}

/// The most points gapchain.sweep() takes: it keeps every row (about 1.5 KB with its vectors)
/// until it returns, where gapchain-sweep streams them to its file.
constexpr long python_sweep_points = 1'000'000;

py::dict sweep_py(const py::object& study_arg, int threads, const py::object& progress) {
    const Study study = to_study(study_arg);
    if (point_count(study) > python_sweep_points)
        throw std::invalid_argument(
            "study: " + std::to_string(point_count(study)) +
            " points; sweep() keeps every row in memory until it returns (about 1.5 KB each): at "
            "most 1000000 here; run gapchain-sweep, which writes each row as it finishes, or "
            "split the study");
    SweepSelection selection;
    selection.threads = threads;
    std::vector<SweepPointResult> rows;
    Call call(progress);
    return call.run(
        [&] {
            return run_study(
                study, selection, [&rows](const SweepPointResult& r) { rows.push_back(r); },
                call.callback());
        },
        [&](SweepEnd end) {
            // Rows arrive in the order they finish; sweep_dict orders them by index.
            py::dict d = sweep_dict(study, rows);
            d["cancelled"] = end == SweepEnd::cancelled;
            return d;
        });
}

} // namespace

void register_regimes(py::module_& m) {
    const ClassifyOptions o;
    m.def("classify", &classify_py, classify_doc, py::arg("scene") = py::none(), py::kw_only(),
          py::arg("transient") = o.transient_periods, py::arg("record") = o.record_periods,
          py::arg("confirm") = o.confirm_by_newton, py::arg("twin") = o.twin_check,
          py::arg("attractors") = 0, py::arg("seed") = py::none(), py::arg("box") = py::none(),
          py::arg("threads") = py::none());
    m.def("regime_map", &regime_map_py, regime_map_doc, py::arg("scene") = py::none(),
          py::kw_only(), py::arg("e_r"), py::arg("f_r"), py::arg("transient") = o.transient_periods,
          py::arg("record") = o.record_periods, py::arg("confirm") = o.confirm_by_newton,
          py::arg("twin") = o.twin_check, py::arg("threads") = 0, py::arg("progress") = py::none());
    m.def("sweep", &sweep_py, sweep_doc, py::arg("study"), py::kw_only(), py::arg("threads") = 0,
          py::arg("progress") = py::none());
}

} // namespace gapchain::python
