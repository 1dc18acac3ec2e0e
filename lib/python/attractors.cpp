// gapchain.attractors and basin_fractions: coexisting attractors from many starts, and their
// basin fractions along one parameter.
#include "call.hpp"

#include "gapchain/attractors.hpp"
#include "gapchain/basin_fractions.hpp"

#include <pybind11/stl.h>

#include <limits>

namespace gapchain::python {

namespace {

constexpr const char* attractors_doc =
    R"(attractors(scene=None, *, samples=200, seed=1, box=1.0, section_points=200, grid=None, resolution=50, threads=0, progress=None, **keys) -> dict

The coexisting attractors of the paper's uniform row (harmonic forcing, linear law) from many
starts: gapchain-attractors in-process (docs/attractors.md). Each start, drawn uniformly in a
box of half-width box x A (A: eq (20)'s contact-free amplitude; velocities box x 2 pi f_r A)
around the scene's initial state (initial.u, initial.v; rest if it gives none), runs the
scene's run section; the runs are grouped into attractors.

samples         random starts, 1 .. 1e7;  seed  their seed, >= 0;  box  [1e-9, 100]
section_points  stroboscopic points kept of a run that does not settle, 20 .. 100000
grid            two state variables ("u1", "v1", ... "uNm", "vNm") for a basin slice of
                resolution x resolution starts (2 .. 2000), the others at the box's center;
                or None
threads         OpenMP threads (0: all); the results do not depend on it
progress        callable(fraction)

Returns a dict: F_m_max (the design value: the largest F_m over the attractors; NaN with none, as
in a call interrupted before any start ended), F_m_max_error,
F_m_max_attractor, unsettled (groups not shown to be attractors: chaotic transients some of
whose starts left for orbits when continued, runs still converging; raise run.periods),
attractors (dict of columns id, regime, period, F_m, F_m_error, lambda_max, lambda_max_error,
basin_fraction, basin_fraction_error, samples, settle_median and settle_max (periods until the
starts' transients ended, NaN where undefined), still_settling (starts whose runs ended still
approaching it), F_m_runs (the largest F_m the starts' runs recorded, transients included) with
F_m_runs_error (that run's F_m_error), members_continued and left_for_orbits (a non-periodic
group: its starts whose runs were continued to confirm it, those that left included, and those
that left it for an orbit; above 0 the group is a chaotic transient, unsettled), and
state: one row of 2 Nm values per attractor, a state on it at phase 0), sample_attractor (per
random start: attractor id, -1 if its run failed), sample_settle_period (per random start: the
period where its transient ended, -1 if it did not settle on an orbit), sample_F_m (per random
start: its run's F_m), sample_start (per random start: its state, 2 Nm values, as starts.csv
writes it: a scene's initial.u and initial.v that run it again), transients (how long the starts' transients last before they reach a
periodic attractor, starts still in a chaotic transient counted as still going:
from_period, the median length; lifetime beyond it and lifetime_error, NaN with fewer than 10
ending beyond it; ended; censored, still going when their runs ended; rate_ratio and its error,
the later half's ending rate over the earlier's; constant_rate, "untested", "consistent" or
"rejected"; periods_until_1_percent, NaN unless consistent),
failed, confirmation_periods (how far the continued members of each non-periodic group ran on beyond
run.periods to confirm it; 0: none), amplitude (A), center (the box's center: 2 Nm reduced values), and with grid: slice_x, slice_y and slice_attractor
(resolution x resolution, rows along y); wall_time_s, cancelled (an interrupted call, by KeyboardInterrupt or an exception progress raises, sets what it had done, cancelled true, as the exception's partial).)";

constexpr const char* basin_fractions_doc =
    R"(basin_fractions(scene=None, *, param="f_r", from_, to, steps, samples=200, seed=1, box=1.0, section_points=200, threads=0, progress=None, **keys) -> dict

attractors() at `steps` values of `param` ("f_r", "e_r", "fc" or "eps") from from_ to to, with
each attractor labelled across the line (seeded from the previous value's attractors, then
by nearest centroid): gapchain-attractors --param in-process. The starts at every value are
drawn in the box around the scene's initial state (rest if it gives none), as in attractors().

Returns a dict: values, and per value x label (label_count columns) arrays fraction,
fraction_error, F_m, F_m_error, period (NaN where the label is absent; period 0 for a
non-periodic attractor); unsettled (per value: groups still converging, whose F_m is a
transient's); transient_lifetime and transient_lifetime_error (per value: the transients'
lifetime of attractors(), NaN where not measured); center (the box's center, 2 Nm reduced
values); label_count, wall_time_s, cancelled (an interrupted call, by KeyboardInterrupt or an exception progress raises, sets what it had done, cancelled true, as the exception's partial).)";

AttractorOptions search_options(const Scene& scene, long samples, std::uint64_t seed, double box,
                                int section_points, int threads) {
    AttractorOptions o;
    o.samples = samples;
    o.seed = seed;
    o.box = box;
    o.section_points = section_points;
    o.threads = threads;
    o.run = scene.run;
    o.center = scene.initial;
    return o;
}

// grid as ("u1", "v1") or "u1,v1" (the CLI's form).
std::vector<std::string> grid_names(const py::object& grid) {
    std::vector<std::string> names;
    if (py::isinstance<py::str>(grid)) {
        const std::string text = grid.cast<std::string>();
        const auto comma = text.find(',');
        if (comma != std::string::npos) names = {text.substr(0, comma), text.substr(comma + 1)};
    } else if (py::isinstance<py::sequence>(grid)) {
        for (const auto& item : grid.cast<py::sequence>()) {
            if (!py::isinstance<py::str>(item)) {
                names.clear();
                break;
            }
            names.push_back(item.cast<std::string>());
        }
    }
    if (names.size() != 2)
        throw std::invalid_argument("grid: expected two state variables, (\"u1\", \"v1\") or "
                                    "\"u1,v1\", got " +
                                    py::repr(grid).cast<std::string>());
    return names;
}

py::dict attractor_columns(const std::vector<Attractor>& as) {
    using A = Attractor;
    py::dict d;
    d["id"] = column<int>(as, [](const A& a) { return a.id; });
    d["regime"] = strings(as, [](const A& a) { return regime_label(a); });
    d["period"] = column<int>(as, [](const A& a) { return a.period; });
    d["F_m"] = column<double>(as, [](const A& a) { return a.F_m; });
    d["F_m_error"] = column<double>(as, [](const A& a) { return a.F_m_error; });
    d["lambda_max"] = column<double>(as, [](const A& a) { return a.lambda_max; });
    d["lambda_max_error"] = column<double>(as, [](const A& a) { return a.lambda_max_error; });
    d["basin_fraction"] = column<double>(as, [](const A& a) { return a.basin_fraction; });
    d["basin_fraction_error"] =
        column<double>(as, [](const A& a) { return a.basin_fraction_error; });
    d["samples"] = column<long>(as, [](const A& a) { return a.samples; });
    d["settle_median"] = column<double>(as, [](const A& a) { return a.settle_median; });
    d["settle_max"] = column<double>(as, [](const A& a) { return a.settle_max; });
    d["still_settling"] = column<long>(as, [](const A& a) { return a.still_settling; });
    d["F_m_runs"] = column<double>(as, [](const A& a) { return a.F_m_runs; });
    d["F_m_runs_error"] = column<double>(as, [](const A& a) { return a.F_m_runs_error; });
    d["members_continued"] = column<long>(as, [](const A& a) { return a.members_continued; });
    d["left_for_orbits"] = column<long>(as, [](const A& a) { return a.left_for_orbits; });
    std::vector<double> states;
    for (const auto& a : as)
        states.insert(states.end(), a.state.begin(), a.state.end());
    d["state"] = matrix(states, as.size(), as.empty() ? 0 : as.front().state.size());
    return d;
}

py::dict set_dict(const AttractorSet& s) {
    py::dict d;
    // No attractor (a search cancelled before any start ended, or every start failed): no
    // design value, where 0 read as one (a hostile probe, helper-85).
    const double none = std::numeric_limits<double>::quiet_NaN();
    d["F_m_max"] = s.F_m_max_id >= 0 ? s.F_m_max : none;
    d["F_m_max_error"] = s.F_m_max_id >= 0 ? s.F_m_max_error : none;
    d["F_m_max_attractor"] = s.F_m_max_id;
    d["unsettled"] = s.unsettled;
    d["attractors"] = attractor_columns(s.attractors);
    d["sample_attractor"] = column<int>(s.sample_attractor, [](int id) { return id; });
    d["sample_settle_period"] = column<long>(s.sample_settle_period, [](long n) { return n; });
    d["sample_F_m"] = array(s.sample_F_m);
    const TransientLifetime& t = s.transients;
    d["transients"] =
        py::dict(py::arg("from_period") = t.from_period, py::arg("lifetime") = t.lifetime,
                 py::arg("lifetime_error") = t.lifetime_error, py::arg("ended") = t.ended,
                 py::arg("censored") = t.censored, py::arg("rate_ratio") = t.rate_ratio,
                 py::arg("rate_ratio_error") = t.rate_ratio_error,
                 py::arg("constant_rate") = std::string(to_string(t.constant_rate)),
                 py::arg("periods_until_1_percent") = t.periods_until(0.01));
    d["failed"] = s.failed;
    d["confirmation_periods"] = s.confirmation_periods;
    d["amplitude"] = s.amplitude;
    if (!s.slice_first.empty()) {
        d["slice_x"] = array(s.slice_first);
        d["slice_y"] = array(s.slice_second);
        d["slice_attractor"] = column<int>(s.slice_attractor, [](int id) {
                                   return id;
                               }).attr("reshape")(s.slice_second.size(), s.slice_first.size());
    }
    d["wall_time_s"] = s.wall_time_s;
    d["cancelled"] = s.cancelled;
    return d;
}

// What the searches set themselves (a keyword for them changed nothing), as the tool refuses.
constexpr const char* search_runs =
    "every start estimates its error and runs no twin; it returns no trajectory";
const std::vector<std::string> search_sets_itself{"run.estimate_error", "run.multistability_check"};

// The forces of a physical scene in newtons: the design value, its error and each attractor's.
void add_newtons(py::dict& d, const AttractorSet& s, const PhysicalParameters& physical) {
    const double none = std::numeric_limits<double>::quiet_NaN();
    d["F_m_max_newton"] = s.F_m_max_id >= 0 ? force_in_newtons(s.F_m_max, physical) : none;
    d["F_m_max_error_newton"] =
        s.F_m_max_id >= 0 ? force_in_newtons(s.F_m_max_error, physical) : none;
    std::vector<double> newtons;
    for (const auto& a : s.attractors)
        newtons.push_back(force_in_newtons(a.F_m, physical));
    d["attractors"].attr("__setitem__")("F_m_newton", array(newtons));
}

// The random starts' states, one row of 2 Nm values each, as starts.csv writes them.
py::array_t<double> start_rows(const AttractorSet& s,
                               const std::vector<std::vector<double>>& starts) {
    const std::size_t rows = s.sample_attractor.size();
    const std::size_t cols = starts.empty() ? 0 : starts.front().size();
    std::vector<double> flat;
    flat.reserve(rows * cols);
    for (std::size_t k = 0; k < rows; ++k)
        flat.insert(flat.end(), starts[k].begin(), starts[k].end());
    return matrix(flat, rows, cols);
}

py::dict attractors_py(const py::object& scene_arg, long samples, std::uint64_t seed, double box,
                       int section_points, const py::object& grid, int resolution, int threads,
                       const py::object& progress, const py::kwargs& keys) {
    refuse_run_keys(keys, "attractors", {"run."}, search_runs, search_sets_itself);
    const Scene scene = to_scene(scene_arg, keys);
    const ReducedParameters& p = paper_row(scene, "attractors");
    AttractorOptions o = search_options(scene, samples, seed, box, section_points, threads);
    if (!grid.is_none()) {
        const auto names = grid_names(grid);
        o.slice = basin_slice(names[0], names[1], p.Nm, resolution);
    } else if (resolution != 50) {
        throw std::invalid_argument("resolution: applies only with grid");
    }
    Call call(progress);
    return call.run([&] { return find_attractors(p, o, call.callback()); },
                    [&](const AttractorSet& s) {
                        py::dict d = set_dict(s);
                        d["center"] = array(box_center(o, p.Nm));
                        d["sample_start"] = start_rows(s, attractor_starts(p, o));
                        if (scene.physical) add_newtons(d, s, *scene.physical);
                        return d;
                    });
}

// values x labels, NaN (or `absent`) where a label is absent at a value.
template <class F>
py::array_t<double> per_label(const FractionContinuation& c, F field, double absent) {
    py::array_t<double> out(
        {static_cast<py::ssize_t>(c.values.size()), static_cast<py::ssize_t>(c.label_count)});
    auto view = out.mutable_unchecked<2>();
    for (std::size_t k = 0; k < c.values.size(); ++k) {
        for (int l = 0; l < c.label_count; ++l)
            view(static_cast<py::ssize_t>(k), l) = absent;
        for (std::size_t i = 0; i < c.sets[k].attractors.size(); ++i)
            view(static_cast<py::ssize_t>(k), c.labels[k][i]) = field(c.sets[k].attractors[i]);
    }
    return out;
}

// The basin-fraction line as basin_fractions() returns it.
py::dict fractions_dict(const FractionContinuation& c, const std::vector<double>& center) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    py::dict d;
    d["values"] = array(c.values);
    d["fraction"] = per_label(
        c, [](const Attractor& a) { return a.basin_fraction; }, nan);
    d["fraction_error"] = per_label(
        c, [](const Attractor& a) { return a.basin_fraction_error; }, nan);
    d["F_m"] = per_label(
        c, [](const Attractor& a) { return a.F_m; }, nan);
    d["F_m_error"] = per_label(
        c, [](const Attractor& a) { return a.F_m_error; }, nan);
    d["period"] = per_label(
        c, [](const Attractor& a) { return double(a.period); }, nan);
    d["unsettled"] = column<int>(c.sets, [](const AttractorSet& set) { return set.unsettled; });
    d["transient_lifetime"] =
        column<double>(c.sets, [](const AttractorSet& set) { return set.transients.lifetime; });
    d["transient_lifetime_error"] = column<double>(
        c.sets, [](const AttractorSet& set) { return set.transients.lifetime_error; });
    d["center"] = array(center);
    d["label_count"] = c.label_count;
    d["wall_time_s"] = c.wall_time_s;
    d["cancelled"] = c.cancelled;
    return d;
}

py::dict basin_fractions_py(const py::object& scene_arg, const std::string& param, double from,
                            double to, int steps, long samples, std::uint64_t seed, double box,
                            int section_points, int threads, const py::object& progress,
                            const py::kwargs& keys) {
    refuse_run_keys(keys, "basin_fractions", {"run."}, search_runs, search_sets_itself);
    const Scene scene = to_swept_scene(scene_arg, param, keys, "basin_fractions");
    const ReducedParameters& p = paper_row(scene, "basin_fractions");
    const std::vector<double> values =
        fraction_line_values(p, parse_swept_parameter(param), from, to, steps);
    const AttractorOptions o = search_options(scene, samples, seed, box, section_points, threads);
    Call call(progress);
    return call.run(
        [&] {
            return continue_basin_fractions(p, parse_swept_parameter(param), values, o,
                                            call.callback());
        },
        [&](const FractionContinuation& c) { return fractions_dict(c, box_center(o, p.Nm)); });
}

} // namespace

void register_attractors(py::module_& m) {
    const AttractorOptions o;
    m.def("attractors", &attractors_py, attractors_doc, py::arg("scene") = py::none(),
          py::kw_only(), py::arg("samples") = o.samples, py::arg("seed") = o.seed,
          py::arg("box") = o.box, py::arg("section_points") = o.section_points,
          py::arg("grid") = py::none(), py::arg("resolution") = 50, py::arg("threads") = 0,
          py::arg("progress") = py::none());
    m.def("basin_fractions", &basin_fractions_py, basin_fractions_doc,
          py::arg("scene") = py::none(), py::kw_only(), py::arg("param") = "f_r", py::arg("from_"),
          py::arg("to"), py::arg("steps"), py::arg("samples") = o.samples, py::arg("seed") = o.seed,
          py::arg("box") = o.box, py::arg("section_points") = o.section_points,
          py::arg("threads") = 0, py::arg("progress") = py::none());
}

} // namespace gapchain::python
