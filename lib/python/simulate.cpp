// gapchain.simulate: one simulation of a row (gapchain-sim in-process).
#include "call.hpp"

#include "gapchain/design_value.hpp"
#include "gapchain/report.hpp"
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
            0 (all cores), refused without attractors; the box around rest, whatever the
            scene's initial state; the paper's uniform row only) and return the design value
            over them and this run as "design_value".
progress    callable(fraction in [0, 1]), called as the run advances.

Returns a dict: F_m and F_m_error (reduced force; physically F = F_m M a0 sqrt(fc); F_m_error
None when not estimated),
F_m_error_method, F_m_contact (j = 0 left wall .. Nm right wall, -1 no contact), F_m_time
(reduced time), contact (bool), multistable (bool: a twin run from a start moved by 1e-8 gave
an F_m beyond the error, or a run that settled late took its F_m in the transient; F_m_error then
covers the difference; None when run.multistability_check is false), F_m_twin (or None), F_m_comparison (the error estimate's comparison
run's F_m, or None), comparison_ended_elsewhere (bool: that run, from the same start on another
step, did not settle where this one did, or settled on an orbit whose largest force differs by
more than max(0.1, 1000 tolerance); the twin run then decides), F_m_orbit (the largest
force over one cycle of the orbit a periodic run settled on, or None), F_m_orbit_error (its
error, from the comparison run where that run settled on the same orbit; None where none did
or the error was not estimated; no start check widens it), maximum_in_transient
(bool: F_m fell before that orbit was reached, F_m_error covers F_m - F_m_orbit; None where
the run settled on no orbit),
start_up_periods and start_up_in_window (a run that did not settle: the periods the row's
start-up takes to decay, and whether the run discarded fewer, so that F_m may be the
start-up's), per_body (Nm x 2 float64: max force on the left and right of
each body), per_body_error (Nm x 2: the errors of the contacts on either side, or None where
no comparison run estimated them), per_body_time (Nm x 2), per_contact (dict of arrays force, time, impacts, Nm + 1
entries, and force_error: an array, or None where no comparison run estimated it), steady_state_period (int or None), steady_state_time, cycle_entry_period (int or
None: the period from which on the state stayed within 1e-3 of repeating, where the transient
ended), longer_cycle_period (int or None: a run with no steady state whose last period states
repeat to run.steady_tolerance with a lag beyond run.max_steady_period, up to 4 times it and
1000; run.max_steady_period set to it lets the run settle), status ("completed",
"steady_state", "non_finite", "cancelled"), message, scheme, step, periods_simulated,
transient_periods_used, steps, evaluations, final_state (2 Nm: u then v), wall_time_s,
accuracy_mode_used, relaxed_from_period (or None), run (the run options), parameters (the
reduced numbers and run settings that ran), scene (its source); physical scenes add F_m_newton,
F_m_error_newton and excitation; model arrays or scatter add chain, a start off rest initial.
These are the keys of gapchain-sim's JSON, from the same writer, with per_body (Nm x 2; its
newtons as per_body_newton), per_body_time and per_contact as arrays, and final_state added.
With trajectory=True, trajectory = {"t": (n,) float64, "state": (n, 2 Nm) float64 with
columns u1..uNm, v1..vNm}. With attractors
> 0, design_value = {F_m_max (the largest of the attractors' F_m and this run's), F_m_max_error,
from_run, start_below (another attractor hits harder beyond both errors), run_above (this run's
F_m is above every attractor's: a transient's), attractors_F_m_max and its error, attractors,
unsettled, failed, samples, seed, box, wall_time_s, attractor (the F_m_max attractor's regime,
period, basin fraction and its error, initial_state; None if none), F_m_max_newton (physical
scenes)}, and multistable is also True when start_below or run_above (gapchain-sim
--attractors).

Bad input raises ValueError naming the key; numerical outcomes are in "status". The GIL is
released while it runs; Ctrl-C (KeyboardInterrupt) stops it.)";

// The JSON gapchain-sim writes (report.cpp, the one list of a result's fields), as a dict, with
// what a NumPy user wants instead of JSON's shapes: per-body and per-contact arrays, the final
// state and the run options (a check that did not run is null there, None here). JSON
// writes a non-finite number as null, which reads as "not estimated": an estimate that came
// out infinite (a comparison run that blew up) is put back as inf.
py::dict result_dict(const std::string& report, const SimulationResult& r, const Scene& scene) {
    py::dict d = py::module_::import("json").attr("loads")(report);
    if (has_error_estimate(r)) {
        d["F_m_error"] = r.F_m_error;
        if (scene.physical) d["F_m_error_newton"] = force_in_newtons(r.F_m_error, *scene.physical);
    }
    std::vector<double> forces, times;
    for (const auto& b : r.per_body) {
        forces.insert(forces.end(), {b.left, b.right});
        times.insert(times.end(), {b.t_left, b.t_right});
    }
    d["per_body"] = matrix(forces, r.per_body.size(), 2);
    d["per_body_time"] = matrix(times, r.per_body.size(), 2);
    if (r.per_contact_error.empty()) {
        d["per_body_error"] = py::none();
    } else {
        std::vector<double> errors;
        for (const auto& b : r.per_body)
            errors.insert(errors.end(), {b.left_error, b.right_error});
        d["per_body_error"] = matrix(errors, r.per_body.size(), 2);
    }
    if (scene.physical) {
        for (double& f : forces)
            f = force_in_newtons(f, *scene.physical);
        d["per_body_newton"] = matrix(forces, r.per_body.size(), 2);
    }
    py::dict contacts = per_contact_dict(r.per_contact);
    contacts["force_error"] = r.per_contact_error.empty() ? py::object(py::none())
                                                          : py::object(array(r.per_contact_error));
    d["per_contact"] = contacts;
    d["message"] = r.message;
    d["final_state"] = array(r.final_state);
    d["run"] = run_dict(scene);
    return d;
}

py::dict simulate_py(const py::object& scene_arg, bool trajectory, long attractors,
                     std::optional<std::uint64_t> seed, std::optional<double> box,
                     std::optional<int> threads, const py::object& progress,
                     const py::kwargs& keys) {
    // As gapchain-sim refuses --set output.trajectory_every without --trajectory.
    if (!trajectory)
        refuse_run_keys(keys, "simulate", {"run."}, "it returns a trajectory with trajectory=True");
    const Scene scene = to_scene(scene_arg, keys);
    const AttractorOptions search =
        design_search(scene, scene.run, "simulate", attractors, seed, box, threads);
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
    py::dict d;
    if (attractors != 0 && r.status != RunStatus::cancelled) {
        const DesignValue design =
            call.run([&] { return design_value(scene.reduced, search, r, call.callback()); });
        d = result_dict(to_json(r, scene, design, search), r, scene);
    } else {
        d = result_dict(to_json(r, scene), r, scene);
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
