// gapchain.simulate: one simulation of a row (gapchain-sim in-process).
#include "call.hpp"

#include "gapchain/attractors.hpp"
#include "gapchain/simulation.hpp"

#include <pybind11/stl.h>

#include <optional>

namespace gapchain::python {

namespace {

constexpr const char* simulate_doc =
    R"(simulate(scene=None, *, trajectory=False, attractors=0, seed=None, box=None, threads=None, progress=None, **keys) -> dict

Simulate a forced, damped row of bodies with clearances and return the maximal reduced impact
force F_m (eq 19) with its error estimate: gapchain-sim in-process, the same numbers.

scene     None (the paper's defaults), a scene dict, or the path of a scene file (JSON, as in
          data/scenes/). Keys given as keywords override it.
**keys    scene keys, short or dotted (run.tolerance=1e-6 as **{"run.tolerance": 1e-6}):
            Nm      bodies, 1 .. 1e6 (default 5)
            fc      stiffness ratio Kc/K, (0, 1e9] (100)
            eps     damping ratio, [0, 100] (0.5)
            e_r     reduced clearance, [0, 1e6] (0.5)
            f_r     reduced forcing frequency f/f0, (0, 1e4] (1.0)
            periods forcing periods, 1 .. 1e9 (1000); transient_periods "auto" or
                    0 .. periods-1; scheme "auto", "rk4", "rkf45", "rk8pd", "exact", ...;
                    tolerance relative accuracy of F_m, 1e-12 .. 0.1 (1e-4); step, steady_state,
                    steady_tolerance, max_steady_period, estimate_error, max_work,
                    multistability_check, accuracy_mode ("auto" or "strict");
                    trajectory_every (output.) decimation in steps, >= 1.
trajectory  also return the (decimated) trajectory of the main run.
attractors  also search the row's attractors from this many random starts, 0 .. 1e7 (as
            attractors(samples=...); seed, box and threads as there, by default 1, 1.0 and
            0 (all cores), refused without attractors; the paper's uniform row only) and
            return the design value over them and this run as "design_value".
progress    callable(fraction in [0, 1]), called as the run advances.

Returns a dict: F_m and F_m_error (reduced force; physically F = F_m M a0 sqrt(fc); F_m_error
None when not estimated),
F_m_error_method, F_m_contact (j = 0 left wall .. Nm right wall, -1 no contact), F_m_time
(reduced time), contact (bool), multistable (bool: a twin run from a start moved by 1e-8 gave
an F_m beyond the error, or a run that settled late took its F_m in the transient; F_m_error then
covers the difference), F_m_twin (or None), F_m_comparison (the error estimate's comparison
run's F_m, or None), comparison_ended_elsewhere (bool: that run, from the same start on another
step, did not settle where this one did, or settled on an orbit whose largest force differs by
more than max(0.1, 1000 tolerance); the twin run then decides), F_m_orbit (the largest
force over one cycle of the orbit a periodic run settled on, or None), maximum_in_transient
(bool: F_m fell before that orbit was reached; F_m_error covers F_m - F_m_orbit), per_body (Nm x 2 float64: max force on the left and right of
each body), per_body_time (Nm x 2), per_contact (dict of arrays force, time, impacts, Nm + 1
entries), steady_state_period (int or None), steady_state_time, cycle_entry_period (int or
None: the period from which on the state stayed within 1e-3 of repeating, where the transient
ended), status ("completed",
"steady_state", "non_finite", "cancelled"), message, scheme, step, periods_simulated,
transient_periods_used, steps, evaluations, final_state (2 Nm: u then v), wall_time_s,
run (the run options), F_m_newton (physical scenes), and with trajectory=True trajectory =
{"t": (n,) float64, "state": (n, 2 Nm) float64 with columns u1..uNm, v1..vNm}. With attractors
> 0, design_value = {F_m_max (the largest of the attractors' F_m and this run's), F_m_max_error,
from_run, start_below (another attractor hits harder beyond both errors), run_above (this run's
F_m is above every attractor's: a transient's), attractors_F_m_max and its error, attractors,
unsettled, failed, samples, seed, box, wall_time_s}, and multistable is also True when
start_below or run_above (gapchain-sim --attractors).

Bad input raises ValueError naming the key; numerical outcomes are in "status". The GIL is
released while it runs; Ctrl-C (KeyboardInterrupt) stops it.)";

py::dict result_dict(const SimulationResult& r, const Scene& scene) {
    py::dict d;
    d["F_m"] = r.F_m;
    d["F_m_error"] = has_error_estimate(r) ? py::object(py::float_(r.F_m_error)) : py::none();
    d["F_m_error_method"] = std::string(to_string(r.error_method));
    d["F_m_contact"] = r.F_m_contact;
    d["F_m_time"] = r.F_m_time;
    d["contact"] = r.contact;
    d["multistable"] = r.multistable;
    d["accuracy_mode_used"] = std::string(to_string(r.accuracy_mode_used));
    d["F_m_twin"] = r.twin_checked ? py::object(py::float_(r.F_m_twin)) : py::object(py::none());
    d["F_m_comparison"] =
        r.F_m_comparison ? py::object(py::float_(*r.F_m_comparison)) : py::object(py::none());
    d["comparison_ended_elsewhere"] = r.comparison_ended_elsewhere;
    d["F_m_orbit"] = r.F_m_orbit ? py::object(py::float_(*r.F_m_orbit)) : py::object(py::none());
    d["maximum_in_transient"] = r.maximum_in_transient;
    std::vector<double> forces, times;
    for (const auto& b : r.per_body) {
        forces.insert(forces.end(), {b.left, b.right});
        times.insert(times.end(), {b.t_left, b.t_right});
    }
    d["per_body"] = matrix(forces, r.per_body.size(), 2);
    d["per_body_time"] = matrix(times, r.per_body.size(), 2);
    d["per_contact"] = per_contact_dict(r.per_contact);
    d["steady_state_period"] = r.steady_state_period ? py::object(py::int_(*r.steady_state_period))
                                                     : py::object(py::none());
    d["steady_state_time"] =
        r.steady_state_time ? py::object(py::float_(*r.steady_state_time)) : py::object(py::none());
    d["cycle_entry_period"] = r.cycle_entry_period >= 0 ? py::object(py::int_(r.cycle_entry_period))
                                                        : py::object(py::none());
    d["status"] = std::string(to_string(r.status));
    d["message"] = r.message;
    d["scheme"] = std::string(to_string(r.scheme));
    d["step"] = r.step;
    d["periods_simulated"] = r.periods_simulated;
    d["transient_periods_used"] = r.transient_periods_used;
    d["steps"] = r.steps;
    d["evaluations"] = r.evaluations;
    d["final_state"] = array(r.final_state);
    d["wall_time_s"] = r.wall_time_s;
    d["run"] = run_dict(scene);
    if (scene.physical) d["F_m_newton"] = force_in_newtons(r.F_m, *scene.physical);
    return d;
}

py::dict design_dict(const DesignValue& d, const AttractorOptions& o) {
    py::dict v;
    v["F_m_max"] = d.F_m_max;
    v["F_m_max_error"] = std::isnan(d.F_m_max_error) ? py::object(py::none())
                                                     : py::object(py::float_(d.F_m_max_error));
    v["from_run"] = d.from_run;
    v["start_below"] = d.start_below;
    v["run_above"] = d.run_above;
    v["attractors_F_m_max"] = d.search.F_m_max;
    v["attractors_F_m_max_error"] = d.search.F_m_max_error;
    v["attractors"] = d.search.attractors.size();
    v["unsettled"] = d.search.unsettled;
    v["failed"] = d.search.failed;
    v["samples"] = o.samples;
    v["seed"] = o.seed;
    v["box"] = o.box;
    v["wall_time_s"] = d.search.wall_time_s;
    return v;
}

py::dict simulate_py(const py::object& scene_arg, bool trajectory, long attractors,
                     std::optional<std::uint64_t> seed, std::optional<double> box,
                     std::optional<int> threads, const py::object& progress,
                     const py::kwargs& keys) {
    const Scene scene = to_scene(scene_arg, keys);
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
        search.run = scene.run;
        validate(paper_row(scene, "simulate(attractors=...)"), search);
    } else if (seed || box || threads) {
        // Given at its default value too: a seed without a search is a mistake either way.
        throw std::invalid_argument(std::string(seed  ? "seed"
                                                : box ? "box"
                                                      : "threads") +
                                    ": applies to the attractor search only; give attractors, "
                                    "1 .. 1e7");
    }
    const Dynamics dyn = scene.dynamics();
    Call call(progress);
    std::vector<double> t, states;
    SimulationHooks hooks;
    hooks.progress = call.callback();
    if (trajectory) {
        const int n = dyn.dimension();
        hooks.trajectory = [&t, &states, n](double time, const double* y) {
            t.push_back(time);
            states.insert(states.end(), y, y + n);
        };
        hooks.trajectory_every = scene.trajectory_every;
    }
    const SimulationResult r =
        call.run([&] { return simulate(dyn, scene.run, scene.initial, hooks); });
    py::dict d = result_dict(r, scene);
    if (attractors != 0 && r.status != RunStatus::cancelled) {
        const DesignValue design =
            call.run([&] { return design_value(scene.reduced, search, r, call.callback()); });
        py::dict v = design_dict(design, search);
        if (scene.physical) v["F_m_max_newton"] = force_in_newtons(design.F_m_max, *scene.physical);
        d["design_value"] = v;
        d["multistable"] = multistable(r, design);
    }
    if (trajectory) {
        py::dict tr;
        tr["t"] = array(t);
        tr["state"] = matrix(states, t.size(), static_cast<std::size_t>(dyn.dimension()));
        d["trajectory"] = tr;
    }
    return d;
}

} // namespace

void register_simulate(py::module_& m) {
    m.def("simulate", &simulate_py, simulate_doc, py::arg("scene") = py::none(), py::kw_only(),
          py::arg("trajectory") = false, py::arg("attractors") = 0L, py::arg("seed") = py::none(),
          py::arg("box") = py::none(), py::arg("threads") = py::none(),
          py::arg("progress") = py::none());
}

} // namespace gapchain::python
