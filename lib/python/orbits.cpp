// gapchain.orbit and continuation: periodic orbits by Newton shooting, and their branches.
#include "call.hpp"

#include "gapchain/continuation.hpp"
#include "gapchain/orbit.hpp"

#include <pybind11/complex.h>
#include <pybind11/stl.h>

namespace gapchain::python {

namespace {

/// The shooting's schemes by name; the message lists those alone (parse_scheme() listed auto
/// and central_difference, which the search then refused).
Scheme shooting_scheme(const std::string& name) {
    if (name == "exact" || name == "rk4" || name == "rkf45" || name == "rk8pd")
        return parse_scheme(name);
    throw std::invalid_argument("scheme: must be one of exact, rk4, rkf45, rk8pd (the "
                                "shooting's schemes), got \"" +
                                name + "\"");
}

constexpr const char* orbit_doc =
    R"(orbit(scene=None, *, period=1, transient=200, tolerance=1e-10, max_iterations=40, scheme="exact", **keys) -> dict

A periodic orbit of the row by Newton shooting on the k-period stroboscopic map x = P^k(x)
(phase 0 of the forcing), started after a plain run of `transient` periods from the scene's
initial state; Floquet multipliers from the exact tangent flow: gapchain-orbit in-process.
Harmonic forcing and the linear contact law only.

period          k, forcing periods of the orbit, 1 .. 1000
transient       periods run before the search, 0 .. 1e7
tolerance       residual |P^k(x) - x| / (1 + |x|) to reach, 1e-14 .. 1e-3
max_iterations  Newton iterations, 1 .. 1000;  scheme  integration of P^k (default exact)

Returns a dict: status ("converged", "not_converged", "singular", "non_finite"), message,
period, minimal_period, state (2 Nm: u then v at phase 0), residual, iterations,
residual_history, multipliers (complex128, largest modulus first), max_multiplier,
max_multiplier_error (its change under one more Newton step; NaN where not estimated), stable,
liouville_error, F_m (over one orbit), F_m_error (its difference from the same orbit on an
independent scheme, rk8pd at 1e-10, rkf45 when scheme is "rk8pd"; NaN where not estimated),
per_contact (dict: force, time, impacts), max_gap,
wall_time_s.)";

constexpr const char* continuation_doc =
    R"(continuation(scene=None, *, param="f_r", from_=2.15, to=4.5, period=1, step=0.01, max_step=0.05, max_points=2000, follow_doublings=False, max_branches=6, transient=200, scheme="exact", progress=None, **keys) -> dict

Pseudo-arclength continuation of the paper's uniform row's periodic orbits in one reduced
parameter, through folds, with folds, period doublings, Neimark-Sacker and grazing points
located on the way: gapchain-continue in-process.

param       "f_r", "e_r", "fc" or "eps";  from_  start value (the first orbit is found there)
to          the branch ends when the parameter leaves [from_, to]
period      k of the first branch, 1 .. 1000;  step  first arclength step, [1e-6, 1]
max_step    largest arclength step, [step, 1];  max_points  points per branch, 1 .. 1e6
follow_doublings  switch to the doubled branch at each period doubling and each non-smooth loss of
                  stability next to -1 (max_branches, 1 .. 64)
transient   periods run before the first Newton search, 0 .. 1e7
scheme      integration of P^k: "exact" (rows of up to 64 bodies), "rk4", "rkf45" or "rk8pd"
progress    callable(fraction)

Returns a dict: points (dict of columns value, period, F_m, F_m_error (as orbit()'s), u1, stable, max_multiplier, branch,
minimal_period, and state: one row of 2 Nm values per point, the orbit's state at phase 0),
special (dict of columns type ("fold", "period_doubling", "neimark_sacker", "grazing",
"branch_point"), value, period, F_m, F_m_error, branch, contact (-1 unless grazing), value_error (the
special point lies within it of value), minimal_period),
branch_end (why each branch ended), unfollowed (branches found and not traced because
max_branches was reached, where each would start), shootings, cancelled (an interrupted call, by KeyboardInterrupt or an exception progress raises, sets what it had done, cancelled true, as the exception's partial), wall_time_s.)";

py::dict orbit_py(const py::object& scene_arg, int period, long transient, double tolerance,
                  int max_iterations, const std::string& scheme, const py::kwargs& keys) {
    refuse_run_keys(keys, "orbit", {"run.max_work"},
                    "its shootings integrate with scheme to 1e-12");
    const Scene scene = to_scene(scene_arg, keys);
    require_linear_harmonic(scene, "orbit()",
                            "the tangent flow assumes a constant Jacobian between switches");
    const Dynamics dyn = scene.dynamics();
    OrbitOptions o;
    o.period = period;
    o.tolerance = tolerance;
    o.max_iterations = max_iterations;
    o.scheme = shooting_scheme(scheme);
    o.max_work = scene.run.max_work;
    Call call;
    const PeriodicOrbit r = call.run([&] {
        return find_periodic_orbit_after(dyn, o, scene.initial, transient, call.callback());
    });
    py::dict d;
    d["status"] = std::string(to_string(r.status));
    d["message"] = r.message;
    d["period"] = r.period;
    d["minimal_period"] = r.minimal_period;
    d["state"] = array(r.state);
    d["residual"] = r.residual;
    d["iterations"] = r.iterations;
    d["residual_history"] = array(r.residual_history);
    d["multipliers"] = py::array(py::cast(r.multipliers));
    d["max_multiplier"] = r.max_multiplier;
    d["stable"] = r.stable;
    d["liouville_error"] = r.liouville_error;
    d["F_m"] = r.F_m;
    d["F_m_error"] = r.F_m_error;
    if (scene.physical) {
        d["F_m_newton"] = force_in_newtons(r.F_m, *scene.physical);
        d["F_m_error_newton"] = force_in_newtons(r.F_m_error, *scene.physical);
    }
    d["max_multiplier_error"] = r.max_multiplier_error;
    d["per_contact"] = per_contact_dict(r.per_contact);
    d["max_gap"] = array(r.max_gap);
    d["wall_time_s"] = r.wall_time_s;
    return d;
}

py::dict continuation_dict(const ContinuationResult& r) {
    using P = BranchPoint;
    using S = SpecialPoint;
    py::dict points;
    points["value"] = column<double>(r.points, [](const P& p) { return p.value; });
    points["period"] = column<int>(r.points, [](const P& p) { return p.period; });
    points["F_m"] = column<double>(r.points, [](const P& p) { return p.F_m; });
    points["F_m_error"] = column<double>(r.points, [](const P& p) { return p.F_m_error; });
    points["u1"] = column<double>(r.points, [](const P& p) { return p.u1; });
    points["stable"] = column<bool>(r.points, [](const P& p) { return p.stable; });
    points["max_multiplier"] =
        column<double>(r.points, [](const P& p) { return p.max_multiplier; });
    points["branch"] = column<int>(r.points, [](const P& p) { return p.branch; });
    points["minimal_period"] = column<int>(r.points, [](const P& p) { return p.minimal_period; });
    // One row per point: the orbit's state at phase 0, a start for orbit() or simulate().
    const py::ssize_t width =
        r.points.empty() ? 0 : static_cast<py::ssize_t>(r.points[0].state.size());
    py::array_t<double> states({static_cast<py::ssize_t>(r.points.size()), width});
    auto rows = states.mutable_unchecked<2>();
    for (std::size_t i = 0; i < r.points.size(); ++i)
        for (py::ssize_t j = 0; j < width; ++j)
            rows(static_cast<py::ssize_t>(i), j) = r.points[i].state[static_cast<std::size_t>(j)];
    points["state"] = states;
    py::dict special;
    special["type"] = strings(r.special, [](const S& s) { return to_string(s.type); });
    special["value"] = column<double>(r.special, [](const S& s) { return s.value; });
    special["period"] = column<int>(r.special, [](const S& s) { return s.period; });
    special["F_m"] = column<double>(r.special, [](const S& s) { return s.F_m; });
    special["F_m_error"] = column<double>(r.special, [](const S& s) { return s.F_m_error; });
    special["branch"] = column<int>(r.special, [](const S& s) { return s.branch; });
    special["contact"] = column<int>(r.special, [](const S& s) { return s.contact; });
    special["value_error"] = column<double>(r.special, [](const S& s) { return s.value_error; });
    special["minimal_period"] = column<int>(r.special, [](const S& s) { return s.minimal_period; });
    py::dict d;
    d["points"] = points;
    d["special"] = special;
    d["branch_end"] = r.branch_end;
    d["unfollowed"] = r.unfollowed;
    d["shootings"] = r.shootings;
    d["cancelled"] = r.cancelled;
    d["wall_time_s"] = r.wall_time_s;
    return d;
}

py::dict continuation_py(const py::object& scene_arg, const std::string& param, double from,
                         double to, int period, double step, double max_step, int max_points,
                         bool follow_doublings, int max_branches, long transient,
                         const std::string& scheme, const py::object& progress,
                         const py::kwargs& keys) {
    refuse_run_keys(keys, "continuation", {"run.max_work"},
                    "its shootings integrate with scheme to 1e-12");
    const Scene scene = to_swept_scene(scene_arg, param, keys, "continuation");
    require_paper_row(scene, "continuation()");
    ContinuationOptions o;
    o.parameter = parse_swept_parameter(param);
    o.from = from, o.to = to, o.period = period;
    o.step = step, o.max_step = max_step, o.max_points = max_points;
    o.follow_doublings = follow_doublings, o.max_branches = max_branches;
    o.transient_periods = transient;
    o.orbit.scheme = shooting_scheme(scheme);
    o.orbit.max_work = scene.run.max_work;
    validate(o);
    Call call(progress);
    return call.run(
        [&] { return continue_orbits(scene.reduced, o, scene.initial, call.callback()); },
        continuation_dict);
}

} // namespace

void register_orbits(py::module_& m) {
    const OrbitOptions o;
    m.def("orbit", &orbit_py, orbit_doc, py::arg("scene") = py::none(), py::kw_only(),
          py::arg("period") = o.period, py::arg("transient") = 200,
          py::arg("tolerance") = o.tolerance, py::arg("max_iterations") = o.max_iterations,
          py::arg("scheme") = "exact");
    const ContinuationOptions c;
    m.def("continuation", &continuation_py, continuation_doc, py::arg("scene") = py::none(),
          py::kw_only(), py::arg("param") = "f_r", py::arg("from_") = c.from, py::arg("to") = c.to,
          py::arg("period") = c.period, py::arg("step") = c.step, py::arg("max_step") = c.max_step,
          py::arg("max_points") = c.max_points, py::arg("follow_doublings") = c.follow_doublings,
          py::arg("max_branches") = c.max_branches, py::arg("transient") = c.transient_periods,
          py::arg("scheme") = "exact", py::arg("progress") = py::none());
}

} // namespace gapchain::python
