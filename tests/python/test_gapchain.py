"""The Python module against the C++ tool gapchain-sim (an independent program writing a JSON
file), and its contract: arrays, errors naming the key, the GIL released, progress and
KeyboardInterrupt. Run by CTest (tests/CMakeLists.txt) with PYTHONPATH at the built package
and GAPCHAIN_SIM / GAPCHAIN_SCENES set."""

import decimal
import glob
import json
import math
import os
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import gapchain

SIM = os.environ.get("GAPCHAIN_SIM", "")
SCENES = sorted(glob.glob(os.path.join(os.environ.get("GAPCHAIN_SCENES", ""), "*.json")))
SHORT = dict(periods=60, transient_periods=20)


def sim_tool(scene_path, tmp_path):
    out = tmp_path / "r.json"
    subprocess.run([SIM, scene_path, "--out", str(out), "--quiet"], check=True)
    return json.loads(out.read_text())


def test_the_shipped_scenes_are_found():
    assert SIM and os.access(SIM, os.X_OK), "GAPCHAIN_SIM must name the built gapchain-sim"
    assert len(SCENES) >= 6, "GAPCHAIN_SCENES must name data/scenes"


@pytest.mark.parametrize("scene_path", SCENES, ids=os.path.basename)
def test_simulate_equals_gapchain_sim_bit_for_bit(scene_path, tmp_path):
    # report.cpp writes doubles with nlohmann::json, which prints the shortest text that reads
    # back as the same double, so == here is equality of the bits.
    tool = sim_tool(scene_path, tmp_path)
    r = gapchain.simulate(scene_path)
    assert r["F_m"] == tool["F_m"]
    assert r["F_m_error"] == tool["F_m_error"]
    assert r["F_m_contact"] == tool["F_m_contact"]
    assert r["status"] == tool["status"]
    assert r["steady_state_period"] == tool["steady_state_period"]
    assert r["per_contact"]["force"].tolist() == [c["force"] for c in tool["per_contact"]]
    assert r["per_contact"]["time"].tolist() == [c["time"] for c in tool["per_contact"]]
    assert r["per_contact"]["impacts"].tolist() == [c["impacts"] for c in tool["per_contact"]]
    errors = [c["force_error"] for c in tool["per_contact"]]
    if None in errors:
        assert r["per_contact"]["force_error"] is None and set(errors) == {None}
    else:
        assert r["per_contact"]["force_error"].tolist() == errors
    assert r["per_body"].tolist() == [[b["left"], b["right"]] for b in tool["per_body"]]
    body_errors = [[b["left_error"], b["right_error"]] for b in tool["per_body"]]
    if None in errors:
        assert r["per_body_error"] is None
    else:
        assert r["per_body_error"].tolist() == body_errors
        assert body_errors == [[errors[i], errors[i + 1]] for i in range(len(body_errors))]
    assert r["F_m_comparison"] == tool.get("F_m_comparison")
    assert r["comparison_ended_elsewhere"] == tool.get("comparison_ended_elsewhere", False)
    if "F_m_newton" in tool:
        assert r["F_m_newton"] == tool["F_m_newton"]
        assert r["per_body_newton"].tolist() == \
            [[b["left_newton"], b["right_newton"]] for b in tool["per_body"]]
    # One writer for both: every key of the tool's JSON is in the dict (F_m_error_newton,
    # excitation and parameters were once the tool's alone).
    assert set(tool) <= set(r), sorted(set(tool) - set(r))
    assert r["parameters"] == tool["parameters"]


def test_a_dict_and_keywords_give_the_scene_file_numbers(tmp_path):
    scene = {"model": {"Nm": 5, "fc": 100, "e_r": 0.5}, "excitation": {"f_r": 1.0}}
    path = tmp_path / "s.json"
    path.write_text(json.dumps(scene))
    tool = sim_tool(str(path), tmp_path)
    assert gapchain.simulate(scene)["F_m"] == tool["F_m"]
    assert gapchain.simulate(Nm=5, fc=100, e_r=0.5, f_r=1.0)["F_m"] == tool["F_m"]
    assert gapchain.simulate(path)["F_m"] == tool["F_m"]  # os.PathLike


def test_result_arrays_have_their_shapes_and_dtypes():
    r = gapchain.simulate(Nm=4, fc=60, e_r=0.06, f_r=3.0, trajectory=True, **SHORT)
    assert r["per_body"].shape == (4, 2) and r["per_body"].dtype == np.float64
    assert r["per_contact"]["force"].shape == (5,)
    assert r["per_contact"]["impacts"].dtype.kind == "i"
    t, state = r["trajectory"]["t"], r["trajectory"]["state"]
    assert state.shape == (t.shape[0], 8) and state.dtype == np.float64
    assert np.all(np.diff(t) > 0)
    m = gapchain.modes(6, 50, count=3)
    assert m["frequency"].shape == (3,) and m["shapes"].shape == (6, 3)
    assert m["mode"].tolist() == [1, 2, 3]
    rm = gapchain.regime_map(Nm=2, e_r=[0.0, 0.5], f_r=[0.5, 1.0, 2.0], transient=10, record=20)
    assert rm["code"].shape == (2, 3) and rm["F_m"].dtype == np.float64
    assert rm["regime"].shape == (2, 3) and rm["regime"].dtype.kind == "U"
    b = gapchain.bifurcation(Nm=5, fc=60, eps=0.5, e_r=0.06, from_=2.9, to=3.2, steps=2,
                             transient=100, record=40)
    assert b["F_m_error"].shape == (2,) and np.all(b["F_m_error"] >= 1e-4 * b["F_m"])
    # 2.9 is period 1, confirmed by Newton with its multiplier; 3.2 is chaotic from rest.
    assert b["newton_confirmed"].tolist() == [True, False]
    assert b["max_multiplier"][0] < 1.0 and np.isnan(b["max_multiplier"][1])
    plain = gapchain.bifurcation(Nm=5, fc=60, eps=0.5, e_r=0.06, from_=2.9, to=2.9, steps=1,
                                 transient=100, record=40, confirm=False)
    assert plain["newton_confirmed"].tolist() == [False]
    # rk4 settles on a period-4 cycle of its own at 4.1092, about the exact period-2 orbit: the
    # row's points are the orbit's two.
    spurious = gapchain.bifurcation(Nm=5, fc=60, eps=0.5, e_r=0.06, from_=4.10921843687,
                                    to=4.10921843687, steps=1, **{"run.scheme": "rk4"})
    assert spurious["points_from_orbit"].tolist() == [True]
    assert spurious["period"].tolist() == [2] and spurious["points"].tolist() == [2]
    assert len(spurious["section"]["point"]) == 2
    assert b["points_from_orbit"].tolist() == [False, False]
    # A start near a basin boundary (docs/bifurcation.md): on this line rk4 from rest settles
    # contact-free at the tenth value, 3.49, where its finer run reaches the impacting orbit.
    edge = gapchain.bifurcation(Nm=3, fc=100, eps=0.2, e_r=0.1, from_=3.40, to=3.50, steps=11,
                                **{"run.scheme": "rk4"})
    assert edge["ended_elsewhere"].tolist() == [k == 9 for k in range(11)]
    assert edge["F_m"][9] == 0.0 and edge["F_m_error"][9] > 1.7
    assert b["ended_elsewhere"].tolist() == [False, False]


def test_modes_match_the_paper_approximation_formula():
    # eq (26), written out here independently of the library.
    Nm, fc = 5, 100
    m = gapchain.modes(Nm, fc)
    k = np.arange(1, Nm + 1) / Nm
    f_ka = np.sqrt(1 + fc * k**2 * (4.935 - 2.935 * k**1.81))
    assert np.allclose(m["approx"], f_ka, rtol=1e-14)
    assert np.allclose(m["rel_error"], (f_ka - m["frequency"]) / m["frequency"], rtol=1e-12)
    # A single body between two walls: f^2 = 1 + 2 fc (both contacts acting), exactly.
    assert gapchain.modes(1, 37)["frequency"][0] == pytest.approx(math.sqrt(75), rel=1e-14)
    # A scene's Nm and fc stand unless given (the probe of 2026-11-26: the defaults 5, 100 won).
    from_scene = gapchain.modes(scene={"model": {"Nm": 1, "fc": 37}})
    assert from_scene["frequency"].tolist() == pytest.approx([math.sqrt(75)], rel=1e-14)
    assert len(gapchain.modes(3, scene={"model": {"Nm": 7}})["frequency"]) == 3


@pytest.mark.parametrize("keys, key", [
    (dict(Nm=0), "model.Nm"),
    (dict(e_r=-1), "model.e_r"),
    (dict(fc=float("nan")), "model.fc"),
    (dict(springiness=2), "springiness"),
    ({"model.springiness": 2}, "model.springiness"),
    (dict(periods=0), "run.periods"),
    (dict(scheme="euler"), "run.scheme"),
    (dict(accuracy_mode="fast"), "run.accuracy_mode"),
])
def test_bad_input_raises_value_error_naming_the_key(keys, key):
    with pytest.raises(ValueError, match=key.replace(".", r"\.")):
        gapchain.simulate(**keys)


def test_bad_analysis_options_raise_value_error():
    with pytest.raises(ValueError, match="end"):
        gapchain.modes(5, 100, end="middle")
    with pytest.raises(ValueError, match="variable"):
        gapchain.bifurcation(variable="u9", steps=2)
    with pytest.raises(ValueError, match="scene"):
        gapchain.simulate(42)
    with pytest.raises(ValueError, match="cannot read"):
        gapchain.simulate("/nonexistent/scene.json")


def test_the_gil_is_released_while_simulate_runs():
    counter = [0]
    stop = threading.Event()

    def count():
        while not stop.is_set():
            counter[0] += 1

    counting = threading.Thread(target=count)
    counting.start()
    try:
        before = counter[0]
        r = gapchain.simulate(Nm=5, fc=60, e_r=0.06, f_r=3.3, periods=40000, steady_state=False,
                              estimate_error=False)
        advanced = counter[0] - before
    finally:
        stop.set()
        counting.join()
    # 3000 periods ran 0.098 s (0.03 s alone) on a quiet machine, under the 0.1 s this needs.
    assert r["wall_time_s"] > 0.1, "the run must be long enough to tell"
    # Held GIL: the counter could only move at the call's ends (a few hundred increments).
    assert advanced > 100000, "the counter advanced only %d while simulate ran" % advanced


def test_progress_is_called_with_fractions_and_its_exception_cancels():
    seen = []
    gapchain.simulate(periods=200, steady_state=False, progress=seen.append)
    assert seen and all(0.0 <= f <= 1.0 for f in seen) and seen == sorted(seen)

    class Stop(Exception):
        pass

    def stop(fraction):
        raise Stop()

    with pytest.raises(Stop):
        gapchain.simulate(periods=2000, steady_state=False, progress=stop)


def test_an_interrupted_call_keeps_what_it_had_done_on_the_exception():
    # A KeyboardInterrupt (or progress's exception) an hour into a diagram lost every finished
    # row; they now ride on the exception as `partial`, with "cancelled" true.
    class Stop(Exception):
        pass

    def stop_at_a_quarter(fraction):
        if fraction >= 0.25:
            raise Stop()

    line = dict(Nm=2, fc=100, eps=0.5, e_r=0.5, from_=1.0, to=2.0, steps=8, transient=20,
                record=20, mode="continuation")
    with pytest.raises(Stop) as stopped:
        gapchain.bifurcation(progress=stop_at_a_quarter, **line)
    partial = stopped.value.partial
    whole = gapchain.bifurcation(**line)
    assert partial["cancelled"] is True and whole["cancelled"] is False
    # Continuation mode runs the 16 rows in order: 4 were done at a quarter.
    assert partial["value"].tolist() == whole["value"][:4].tolist()
    assert partial["F_m"].tolist() == whole["F_m"][:4].tolist()
    study = {"scene": {"run": {"periods": 40}}, "parameters": {"e_r": [0.1, 0.2, 0.3, 0.4]}}
    with pytest.raises(Stop) as stopped:
        gapchain.sweep(study, threads=1, progress=stop_at_a_quarter)
    rows = stopped.value.partial
    assert rows["cancelled"] is True and 1 <= len(rows["index"]) < 4
    assert rows["F_m"][0] == gapchain.sweep(study, threads=1)["F_m"][0]
    # Work not done is not reported as data: a map's cells not run read "not run" with NaN
    # forces (they read no-contact with F_m 0), a diagram's rows not run are left out (they
    # read F_m 0 +- 0).
    with pytest.raises(Stop) as stopped:
        gapchain.regime_map(e_r=[0.3], f_r=[1.0, 1.1, 1.2, 1.3], transient=20, record=20,
                            threads=1, progress=stop_at_a_quarter, Nm=2, fc=100, eps=0.5)
    cells = stopped.value.partial
    assert cells["cancelled"] is True and cells["regime"][0][-1] == "not run"
    assert np.isnan(cells["F_m"][0][-1]) and cells["code"][0][-1] == -1
    assert cells["regime"][0][0] != "not run" and cells["F_m"][0][0] > 0
    with pytest.raises(Stop) as stopped:
        gapchain.bifurcation(progress=stop_at_a_quarter, threads=1,
                             **dict(line, mode="independent"))
    diagram = stopped.value.partial
    assert 1 <= len(diagram["value"]) < 8 and all(s != "cancelled" for s in diagram["status"])
    # An attractor search stopped before any start ended has no design value: it read 0 +- 0
    # (a hostile probe, helper-85).
    def stop_at_once(fraction):
        raise Stop()

    with pytest.raises(Stop) as stopped:
        gapchain.attractors(samples=8, threads=1, progress=stop_at_once, Nm=3, fc=100, eps=0.5,
                            e_r=0.1, f_r=1.5)
    search = stopped.value.partial
    assert search["cancelled"] is True and len(search["attractors"]["id"]) == 0
    assert np.isnan(search["F_m_max"]) and np.isnan(search["F_m_max_error"])


def test_keyboard_interrupt_stops_a_long_run():
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        gapchain.simulate(Nm=50, periods=10**6, steady_state=False, estimate_error=False)
    assert time.monotonic() - start < 5.0


def test_sweep_columns_follow_the_study():
    study = {"scene": {"run": {"periods": 40}}, "parameters": {"fc": [1, 10], "e_r": [0.1, 0.2]},
             "keep": ["per_body", "F_m_orbit"]}
    s = gapchain.sweep(study, threads=2)
    assert s["index"].tolist() == [0, 1, 2, 3]
    assert s["fc"].tolist() == [1, 1, 10, 10] and s["e_r"].tolist() == [0.1, 0.2, 0.1, 0.2]
    assert s["per_body"].shape == (4, 5, 2)
    assert s["multistable"].dtype == np.bool_ and s["maximum_in_transient"].dtype == np.bool_
    one = gapchain.simulate(fc=10, e_r=0.2, periods=40)
    assert s["F_m"][3] == one["F_m"]
    assert s["F_m_error"][3] == one["F_m_error"]
    assert s["maximum_in_transient"][3] == one["maximum_in_transient"]
    orbit = one["F_m_orbit"]
    assert (np.isnan(s["F_m_orbit"][3]) if orbit is None else s["F_m_orbit"][3] == orbit)
    bar = one["F_m_orbit_error"]
    assert (np.isnan(s["F_m_orbit_error"][3]) if bar is None
            else s["F_m_orbit_error"][3] == bar)
    assert s["per_body_error"].shape == (4, 5, 2)
    if one["per_body_error"] is None:
        assert np.all(np.isnan(s["per_body_error"][3]))
    else:
        assert s["per_body_error"][3].tolist() == one["per_body_error"].tolist()


def test_a_sweep_names_a_cycle_longer_than_max_steady_period():
    # The period-18 orbit of test_simulation's long-cycle case; the default test tries 16.
    scene = {"model": {"Nm": 5, "fc": 10, "eps": 0.1, "e_r": 0.06}, "excitation": {"f_r": 1.6},
             "initial": {"u": [0.3, -0.2, 0.1, 0.0, 0.2]}, "run": {"periods": 1000}}
    s = gapchain.sweep({"scene": scene, "parameters": {"run.max_steady_period": [16, 18]}})
    assert s["steady_state_period"].tolist() == [0, 18]
    assert s["longer_cycle_period"].tolist() == [18, 0]
    assert gapchain.simulate(scene)["longer_cycle_period"] == 18


def test_a_physical_sweep_gives_F_m_and_its_error_in_newtons():
    scene = {"units": "physical", "model": {"Nm": 3, "M": 100, "K": 1e5, "C": 500, "Kc": 5e6,
             "e": 0.002}, "excitation": {"a0": 5, "f": 4},
             "run": {"periods": 300, "transient_periods": 150}}
    s = gapchain.sweep({"scene": scene, "parameters": {"model.e": [0.002, 0.003]}})
    one = gapchain.simulate(scene)
    assert s["F_m_newton"][0] == one["F_m_newton"]
    assert s["F_m_error_newton"][0] == one["F_m_error_newton"]
    assert np.allclose(s["F_m_error_newton"] / s["F_m_error"], s["F_m_newton"] / s["F_m"],
                       rtol=1e-12)
    # The design value, an attractor search's and an orbit's F_m, in newtons too.
    newtons = one["F_m_newton"] / one["F_m"]
    d = gapchain.sweep({"scene": scene, "parameters": {"model.e": [0.002]}, "attractors": 4})
    assert d["F_m_max_newton"][0] == pytest.approx(d["F_m_max"][0] * newtons, rel=1e-12)
    a = gapchain.attractors(scene, samples=4)
    assert a["F_m_max_newton"] == pytest.approx(a["F_m_max"] * newtons, rel=1e-12)
    assert np.allclose(a["attractors"]["F_m_newton"], a["attractors"]["F_m"] * newtons)
    o = gapchain.orbit(scene)
    assert o["F_m_newton"] == pytest.approx(o["F_m"] * newtons, rel=1e-12)
    # A Kanai-Tajimi motion has no forcing frequency: f_r is NaN, not the reduced 1.
    quake = {"units": "physical", "model": scene["model"],
             "excitation": {"type": "kanai_tajimi", "a0": 5, "ground_frequency": 2.5,
                            "ground_damping": 0.6, "duration": 1.0, "sample_interval": 0.005,
                            "rise": 0.2, "hold": 0.5, "decay": 0.5, "seed": 1}}
    q = gapchain.sweep({"scene": quake, "parameters": {"model.e": [0.002]}})
    assert np.isnan(q["f_r"][0]) and np.isfinite(q["F_m"][0])
    assert s["f_r"][0] == pytest.approx(4 / (math.sqrt(1e5 / 100) / (2 * math.pi)), rel=1e-12)


def test_accuracy_mode_is_reported_and_strict_keeps_a_periodic_answer():
    auto = gapchain.simulate(periods=200)
    strict = gapchain.simulate(periods=200, accuracy_mode="strict")
    assert auto["accuracy_mode_used"] == "strict" == strict["accuracy_mode_used"]
    assert abs(auto["F_m"] - strict["F_m"]) <= 1e-9 * strict["F_m"]


def test_continuation_takes_a_scheme_and_the_exact_one_stops_at_64_bodies():
    # The tool's --scheme, in Python too: rows above 64 bodies had no way past exact.
    with pytest.raises(ValueError, match="scheme: exact takes rows of up to 64 bodies"):
        gapchain.continuation(Nm=65, fc=60, e_r=0.06, from_=2.9, to=2.91)
    r = gapchain.continuation(MIRROR_PAIR, from_=1.2, to=1.21, scheme="rk4", max_points=2,
                              transient=50)
    assert len(r["points"]["value"]) >= 1
    with pytest.raises(ValueError, match="^scheme: must be one of"):
        gapchain.continuation(MIRROR_PAIR, from_=1.2, to=1.21, scheme="euler")


def test_continuation_points_carry_their_orbit_state():
    # Fig 13's row: the state of each continued orbit is a start that gapchain.orbit, with no
    # transient, confirms as the same orbit.
    row = {"model": {"Nm": 5, "fc": 60, "eps": 0.5, "e_r": 0.06}, "excitation": {"f_r": 3.0}}
    r = gapchain.continuation(row, param="f_r", from_=2.15, to=2.2)
    states = r["points"]["state"]
    assert states.shape == (len(r["points"]["value"]), 10)
    assert np.array_equal(states[:, 0], r["points"]["u1"])
    i = len(states) // 2
    start = dict(row, excitation={"f_r": float(r["points"]["value"][i])},
                 initial={"u": states[i, :5].tolist(), "v": states[i, 5:].tolist()})
    found = gapchain.orbit(start, transient=0)
    assert found["status"] == "converged"
    assert abs(found["F_m"] - r["points"]["F_m"][i]) < 1e-7


MIRROR_PAIR = {"model": {"Nm": 1, "fc": 100, "eps": 0.1, "e_r": 0.6}, "excitation": {"f_r": 1.2},
               "run": {"periods": 600}}


def test_classify_against_the_attractors_calls_a_saddles_chaos_a_transient():
    # Fig 13's row at f_r = 2.05 reads chaotic from rest on a chaotic saddle's transient; its one
    # attractor is the period-3 orbit of F_m 1.15579 (docs/attractors.md).
    scene = os.path.join(os.environ.get("GAPCHAIN_SCENES", ""), "fig13.json")
    c = gapchain.classify(scene, f_r=2.05, attractors=8)
    assert c["regime"] == "chaotic"
    assert c["label_in_search"] == "transient" and c["multistable"]
    assert c["design_value"]["start_below"]
    assert abs(c["design_value"]["F_m_max"] - 1.15579) < 1e-5
    assert c["design_value"]["attractor"]["period"] == 3
    plain = gapchain.classify(scene, f_r=2.05)
    assert "design_value" not in plain and "label_in_search" not in plain
    for extra in ({"seed": 3}, {"box": 1.0}, {"threads": 0}):
        name = next(iter(extra))
        with pytest.raises(ValueError, match="^%s: applies to the attractor search only" % name):
            gapchain.classify(scene, f_r=2.05, **extra)
    with pytest.raises(ValueError, match="^attractors: must be an integer in"):
        gapchain.classify(scene, f_r=2.05, attractors=-1)


def test_simulate_design_value_matches_gapchain_sim(tmp_path):
    # Fig 13's line at f_r = 3.2: from rest the weaker attractor, the torus is the design value.
    keys = dict(f_r=3.2, periods=600, transient_periods=300)
    scene = os.path.join(os.environ.get("GAPCHAIN_SCENES", ""), "fig13.json")
    r = gapchain.simulate(scene, attractors=30, seed=2, **keys)
    v = r["design_value"]
    assert r["multistable"] and v["start_below"] and v["F_m_max"] > r["F_m"]
    out = tmp_path / "d.json"
    subprocess.run([SIM, scene, "--set", "excitation.f_r=3.2", "--set", "run.periods=600",
                    "--set", "run.transient_periods=300", "--attractors", "30", "--seed", "2",
                    "--out", str(out), "--quiet"], check=True)
    tool = json.loads(out.read_text())["design_value"]
    for key in ("F_m_max", "F_m_max_error", "start_below", "run_above", "attractors"):
        assert v[key] == tool[key], key
    assert set(tool) <= set(v), sorted(set(tool) - set(v))
    assert v["attractor"] == tool["attractor"]
    assert "design_value" not in gapchain.simulate(scene, **keys)
    # Refused whatever the value, the default's too: without a search nothing reads it.
    for extra in ({"seed": 3}, {"seed": 1}, {"box": 1.0}, {"threads": 0}):
        name = next(iter(extra))
        with pytest.raises(ValueError, match="^%s: applies to the attractor search only" % name):
            gapchain.simulate(scene, **extra, **keys)
    with pytest.raises(TypeError, match="^seed: must be an integer or None, got 1.5"):
        gapchain.simulate(scene, seed=1.5, **keys)
    # 0 is valid (no search): the range says so, and an integer is asked, not "a finite number".
    with pytest.raises(ValueError, match=r"^attractors: must be an integer in \[0, 10000000\]"):
        gapchain.simulate(scene, attractors=-1, **keys)
    with pytest.raises(ValueError, match=r"^samples: must be an integer in \[1, 10000000\]"):
        gapchain.attractors(scene, samples=0)
    # A row the search does not take is named with the call as written (it read
    # "simulate(attractors=...)() takes").
    with pytest.raises(ValueError, match=r"^model.contact_law: simulate\(\) with attractors=2 takes"):
        gapchain.simulate(scene, attractors=2, **{"model.contact_law": "hertz"}, **keys)


def test_attractors_match_gapchain_attractors(tmp_path):
    # Nm = 1 between the walls: two mirror-image period-1 orbits of equal F_m (MODEL.md §5).
    a = gapchain.attractors(MIRROR_PAIR, samples=40, box=2, grid=("u1", "v1"), resolution=4)
    columns = a["attractors"]
    assert len(columns["id"]) == 2 and columns["state"].shape == (2, 2)
    assert columns["F_m"][0] == pytest.approx(columns["F_m"][1], rel=1e-9)
    assert a["F_m_max"] == max(columns["F_m"])
    assert a["slice_attractor"].shape == (4, 4) and set(np.unique(a["slice_attractor"])) <= {0, 1}
    assert columns["basin_fraction"].sum() == pytest.approx(1.0)
    scene = tmp_path / "mirror.json"
    scene.write_text(json.dumps(MIRROR_PAIR))
    tool = os.path.join(os.path.dirname(SIM), "gapchain-attractors")
    subprocess.run([tool, str(scene), "--samples", "40", "--box", "2", "--no-plot", "--out",
                    str(tmp_path / "a")], check=True, stdout=subprocess.DEVNULL)
    written = json.loads((tmp_path / "a" / "attractors.json").read_text())
    assert [x["F_m"] for x in written["attractors"]] == columns["F_m"].tolist()
    assert [x["basin_fraction"] for x in written["attractors"]] == \
        columns["basin_fraction"].tolist()
    # Per start: where its transient ended, as starts.csv says; the per-attractor statistics.
    rows = (tmp_path / "a" / "starts.csv").read_text().splitlines()
    assert rows[0] == "start,attractor,settle_period,F_m_run,u1,v1" and len(rows) == 41
    assert [int(r.split(",")[2]) for r in rows[1:]] == a["sample_settle_period"].tolist()
    # Each start's state, which runs it again (an independent review, helper-88: only each
    # attractor's first start was written). Run from it, a start ends on the orbit the search
    # put it on: the mirror pair's two orbits differ in sign.
    starts = np.array([[float(x) for x in r.split(",")[4:]] for r in rows[1:]])
    assert np.array_equal(starts, a["sample_start"]) and starts.shape == (40, 2)
    for k in (0, 1, 2):
        rerun = gapchain.simulate(MIRROR_PAIR, **{"initial.u": [starts[k][0]],
                                                  "initial.v": [starts[k][1]]})
        distances = [np.abs(rerun["final_state"] - orbit).max() for orbit in columns["state"]]
        assert np.argmin(distances) == a["sample_attractor"][k]
        assert rerun["F_m"] == pytest.approx(a["sample_F_m"][k], rel=1e-9)
    assert a["sample_F_m"].shape == (40,)
    # The transients' lifetime, as attractors.json says (NaN there is null).
    nan_as_none = {k: (None if isinstance(v, float) and np.isnan(v) else v)
                   for k, v in a["transients"].items()}
    assert nan_as_none == written["transients"]
    # Every start settled here: the Kaplan-Meier median is then the ceil(n/2)-th length.
    settled = np.sort(a["sample_settle_period"])
    assert settled[0] >= 0 and a["transients"]["censored"] == 0
    assert a["transients"]["from_period"] == settled[(len(settled) + 1) // 2 - 1]
    for i in range(2):
        members = a["sample_settle_period"][a["sample_attractor"] == i]
        settled = members[members >= 0]
        assert columns["still_settling"][i] == np.count_nonzero(members < 0)
        assert columns["settle_max"][i] == settled.max()
        assert columns["F_m_runs"][i] >= columns["F_m"][i] * (1 - 1e-4)
        # Two periodic attractors: no group to confirm, no start that left one.
        assert columns["members_continued"][i] == 0 and columns["left_for_orbits"][i] == 0
    assert [x["left_for_orbits"] for x in written["attractors"]] == \
        columns["left_for_orbits"].tolist()


def test_basin_fractions_label_each_attractor_along_the_line():
    f = gapchain.basin_fractions(MIRROR_PAIR, from_=1.2, to=1.22, steps=2, samples=20, box=2)
    assert f["values"].tolist() == [1.2, 1.22]
    assert f["fraction"].shape == (2, f["label_count"])
    assert np.nansum(f["fraction"], axis=1) == pytest.approx([1.0, 1.0])
    assert np.all(np.isnan(f["F_m"]) == np.isnan(f["fraction"]))


def test_numpy_values_in_dicts_and_non_finite_numbers_name_their_key():
    base = {"model": {"Nm": np.int32(2), "fc": np.float64(100.0), "e_r": 0.5}}
    assert gapchain.simulate(base, **SHORT)["F_m"] == \
        gapchain.simulate({"model": {"Nm": 2, "fc": 100.0, "e_r": 0.5}}, **SHORT)["F_m"]
    # A non-finite value names its key and the key's range (the probe of 2026-11-26: no range).
    with pytest.raises(ValueError, match=r"^model\.fc: must be a finite number in \(0, 1000000000\], got nan$"):
        gapchain.simulate({"model": {"fc": float("nan")}})
    with pytest.raises(ValueError, match=r"^run\.periods: must be an integer in \[1, 1000000000\]"):
        gapchain.simulate({"run": {"periods": float("inf")}})
    with pytest.raises(ValueError, match=r"^model\.mass\[1\]: must be a finite number, got nan$"):
        gapchain.simulate({"model": {"Nm": 3, "mass": [1, float("nan"), 1]}})
    with pytest.raises(ValueError, match=r"model\.fc: must be a number"):
        gapchain.simulate({"model": {"fc": 1j}})
    with pytest.raises(ValueError, match=r"run\.periods"):
        gapchain.attractors(MIRROR_PAIR, periods=10)
    # One key by its short and its dotted name: named in keywords, not in the CLI's --set.
    with pytest.raises(ValueError, match=r"^model\.fc: given twice, as the keywords fc and model\.fc$"):
        gapchain.simulate(None, fc=1, **{"model.fc": 2})


def test_a_sweep_with_attractors_has_the_design_value_columns():
    study = {"scene": MIRROR_PAIR, "parameters": {"e_r": np.array([0.6])}, "attractors": 8}
    s = gapchain.sweep(study)
    assert s["attractors"].tolist() == [2]
    assert s["F_m_max"][0] >= s["F_m"][0]


def test_an_argument_of_the_wrong_type_is_named_in_one_line():
    cases = [(gapchain.attractors, {"samples": 1.5}, "samples: must be an integer, got 1.5"),
             (gapchain.orbit, {"period": 3.0}, "period: must be an integer, got 3.0"),
             (gapchain.classify, {"transient": None}, "transient: must be an integer, got None"),
             (gapchain.classify, {"confirm": None}, "confirm: must be True or False, got None"),
             (gapchain.bifurcation, {"confirm": None}, "confirm: must be True or False, got None"),
             (gapchain.simulate, {"trajectory": "yes"}, "trajectory: must be True or False"),
             (gapchain.regime_map, {"e_r": [0.1, "x"], "f_r": [1.0]},
              "e_r: must be a list of numbers"),
             # pybind11 would take these silently: True as 1, 3.7 as 3, a 2-D array's rows.
             (gapchain.attractors, {"samples": True}, "samples: must be an integer, got True"),
             (gapchain.attractors, {"samples": np.float32(3.7)}, "samples: must be an integer"),
             (gapchain.attractors, {"box": True}, "box: must be a number, got True"),
             # An array of one entry has __float__: it ran as box=1.
             (gapchain.attractors, {"box": np.array([1.0])}, r"box: must be a number, got array"),
             (gapchain.simulate, {"trajectory": 0.5}, "trajectory: must be True or False"),
             (gapchain.regime_map, {"e_r": np.zeros((20, 20)), "f_r": [1.0]},
              r"e_r: must be a list of numbers, got array\(\[\[0\."),
             (gapchain.simulate, {"progress": 1}, "progress: must be a callable"),
             (gapchain.simulate, {"scene": MIRROR_PAIR}, "simulate\\(\\): got two values for scene"),
             # A misspelt keyword of a function without scene keys is named (it was "arguments
             # of the wrong type").
             (gapchain.sweep, {"thread": 2}, r"thread: unknown keyword of sweep\(\)")]
    for function, kwargs, message in cases:
        with pytest.raises(TypeError, match=message) as raised:
            function(MIRROR_PAIR, **kwargs)
        assert "\n" not in str(raised.value)
    with pytest.raises(TypeError, match=r"attractors\(\): takes 1 positional argument"):
        gapchain.attractors(MIRROR_PAIR, True)
    # An integer beyond the doubles is a value out of range, named (it was "arguments of the
    # wrong type").
    with pytest.raises(ValueError, match=r"^from_: must be a finite number"):
        gapchain.basin_fractions(MIRROR_PAIR, from_=10 ** 400, to=1.1, steps=2)
    # Errors name the Python argument, not the library's option behind it.
    with pytest.raises(ValueError, match=r"^record: must be"):
        gapchain.classify(MIRROR_PAIR, record=0)
    with pytest.raises(ValueError, match=r"^transient: must be"):
        gapchain.orbit(MIRROR_PAIR, transient=-5)
    with pytest.raises(ValueError, match=r"^resolution: must be an integer in \[2, 2000\]"):
        gapchain.attractors(MIRROR_PAIR, grid=("u1", "v1"), resolution=0)
    with pytest.raises(ValueError, match=r"^param: must be one of f_r, e_r, fc, eps"):
        gapchain.continuation(MIRROR_PAIR, param="xx")
    with pytest.raises(ValueError, match=r"^phase: must be in \[0, 1\)"):
        gapchain.bifurcation(MIRROR_PAIR, phase=7.0)
    with pytest.raises(ValueError, match=r"^scheme: "):
        gapchain.orbit(MIRROR_PAIR, scheme="bogus")
    with pytest.raises(ValueError, match=r"^to: "):
        gapchain.basin_fractions(MIRROR_PAIR, from_=1.0, to=-2.0, steps=3)
    # A scene keyword of a kind JSON cannot hold names its key.
    with pytest.raises(ValueError, match="model.fc: must be a number, string, list or object"):
        gapchain.simulate(fc=decimal.Decimal("3"))
    # What pybind11 took before and users pass: flags as 0 or 1, any sequence, 0-d arrays,
    # Decimal for a number; a string keyword reaches the scene parser unchanged. None is no
    # flag: classify(confirm=None) skipped the Newton confirmation it defaults to.
    assert "trajectory" in gapchain.simulate(MIRROR_PAIR, trajectory=1, **SHORT)
    assert "trajectory" not in gapchain.simulate(MIRROR_PAIR, trajectory=0, **SHORT)
    with pytest.raises(TypeError, match="^trajectory: must be True or False, got None"):
        gapchain.simulate(MIRROR_PAIR, trajectory=None, **SHORT)
    assert gapchain.orbit(MIRROR_PAIR, period=np.array(1),
                          tolerance=decimal.Decimal("1e-10"))["status"] == "converged"
    assert gapchain.regime_map(MIRROR_PAIR, e_r=range(1, 2), f_r=(1.2,), transient=10,
                               record=20)["regime"].shape == (1, 1)
    assert gapchain._scene_json("/data/NaN_Infinity.csv", "excitation.file") == \
        '"/data/NaN_Infinity.csv"'
    # The wrapper keeps the name and the help text, and lets right-typed calls through.
    assert gapchain.attractors.__name__ == "attractors"
    assert gapchain.attractors.__doc__.startswith("attractors(scene=None")
    assert gapchain.orbit(MIRROR_PAIR, period=np.int64(1))["status"] == "converged"


def test_an_error_nothing_estimated_is_none_or_nan_not_zero():
    # Fig 5's periodic point settles early: no twin or orbit check widens the error bar.
    r = gapchain.simulate(Nm=5, fc=100, eps=0.5, e_r=0.5, f_r=1.0, periods=200,
                          estimate_error=False)
    assert r["F_m"] > 0 and r["F_m_error"] is None and r["F_m_error_method"] == "none"
    study = {"scene": {"model": {"Nm": 5, "fc": 100, "eps": 0.5, "e_r": 0.5},
                       "run": {"periods": 200, "estimate_error": False}},
             "parameters": {"f_r": [1.0]}}
    assert np.isnan(gapchain.sweep(study)["F_m_error"][0])
    assert gapchain.simulate(Nm=5, fc=100, eps=0.5, e_r=0.5, f_r=1.0, periods=200)["F_m_error"] > 0


def test_a_keyword_of_the_swept_parameter_is_refused():
    # The CLI refuses --set of the parameter a tool varies; the keyword was silently replaced.
    with pytest.raises(ValueError, match="^f_r: continuation\\(\\) varies f_r itself"):
        gapchain.continuation(from_=3, to=3.1, f_r=3.0, Nm=5, fc=60, eps=0.5, e_r=0.06)
    with pytest.raises(ValueError, match="^eps: basin_fractions\\(\\) varies eps itself"):
        gapchain.basin_fractions(param="eps", from_=0.1, to=0.2, steps=2, eps=5.0)
    with pytest.raises(ValueError, match="^excitation.f_r: bifurcation\\(\\) varies f_r"):
        gapchain.bifurcation(param="f_r", from_=2, to=3, steps=2, **{"excitation.f_r": 3.0})
    # So is a physical scene's key that enters the swept number alone (e_r's model.e).
    physical = next(p for p in SCENES if p.endswith("table4-experiment-harmonic.json"))
    with pytest.raises(ValueError, match="^model.e: bifurcation\\(\\) varies e_r itself"):
        gapchain.bifurcation(physical, param="e_r", from_=0.1, to=0.2, steps=2,
                             **{"model.e": 0.004})
    # regime_map's axes too (the map ignored them).
    with pytest.raises(ValueError, match="^model.e_r: regime_map\\(\\) varies e_r itself"):
        gapchain.regime_map(e_r=[0.3], f_r=[0.6], **{"model.e_r": 0.9})
    with pytest.raises(ValueError, match="^excitation.f_r: regime_map\\(\\) varies f_r"):
        gapchain.regime_map(e_r=[0.3], f_r=[0.6], **{"excitation.f_r": 2.0})


def test_a_start_is_honoured_where_a_run_starts_and_centers_the_box_where_starts_are_drawn():
    # Issue 19's Fig 13 point: chaotic from rest, a torus (F_m 0.385) from this start. classify()
    # and bifurcation() ignored a scene's initial state; the attractor search refused it, and
    # now draws its starts around it: a small box there finds the torus alone.
    row = dict(Nm=5, fc=60, eps=0.5, e_r=0.06, f_r=3.2)
    start = {"initial": {"u": [0.5, -0.5, 0.5, -0.5, 0.5]}}
    scene = {"model": {k: row[k] for k in ("Nm", "fc", "eps", "e_r")},
             "excitation": {"f_r": 3.2}, **start}
    assert gapchain.classify(scene)["regime"] == "quasi-periodic"
    assert gapchain.classify(None, **row)["regime"] == "chaotic"
    diagram = gapchain.bifurcation(scene, param="e_r", from_=0.06, to=0.06, steps=1,
                                   transient=300, record=300)
    assert abs(diagram["F_m"][0] - 0.385) < 1e-3
    run = dict(periods=600, transient_periods=300)
    near = gapchain.attractors(scene, samples=4, box=1e-3, **run)
    assert list(near["attractors"]["regime"]) == ["quasi-periodic"]
    assert list(near["attractors"]["samples"]) == [4]
    assert abs(near["F_m_max"] - 0.3853) < 1e-3
    assert list(near["center"]) == [0.5, -0.5, 0.5, -0.5, 0.5] + [0.0] * 5
    line = gapchain.basin_fractions(scene, param="f_r", from_=3.15, to=3.2, steps=2, samples=4,
                                    box=1e-3, **run)
    assert abs(line["F_m"][1][0] - 0.3853) < 1e-3 and line["fraction"][1][0] == 1.0
    assert list(line["center"]) == list(near["center"])


def test_a_seed_out_of_range_is_a_value_error_with_the_library_limit_and_long_doubles_pass():
    # -1 was a TypeError naming [0, 2**64), 2**63 a ValueError naming the library's [0, 2^62].
    for seed in (-1, 2 ** 62 + 1, 2 ** 63, 2 ** 64):
        with pytest.raises(ValueError, match=r"^seed: must be an integer in \[0, 2\^62 = 4611686018427387904\]"):
            gapchain.attractors(samples=2, seed=seed)
    # A NumPy long double in a scene dict recursed without end; it is a number like any other.
    plain = gapchain.simulate({"model": {"fc": 100.0}}, periods=50)["F_m"]
    assert gapchain.simulate({"model": {"fc": np.longdouble(100)}}, periods=50)["F_m"] == plain
    with pytest.raises(ValueError, match="^model.fc: must be a number"):
        gapchain.simulate({"model": {"fc": np.clongdouble(100)}}, periods=50)
    # Finite, but beyond the double range: not "got inf".
    with pytest.raises(ValueError, match="^model.fc: must be a finite number within the double"):
        gapchain.simulate({"model": {"fc": np.longdouble("1e400")}}, periods=50)


def test_orbit_and_continuation_refuse_run_keywords_they_would_ignore():
    # continuation(tolerance=0.1) ran, the scene's run.tolerance unread by the shootings.
    with pytest.raises(ValueError, match="^tolerance: continuation\\(\\) does not read"):
        gapchain.continuation(MIRROR_PAIR, from_=1.2, to=1.21, tolerance=0.1)
    with pytest.raises(ValueError, match="^run.periods: orbit\\(\\) does not read"):
        gapchain.orbit(MIRROR_PAIR, **{"run.periods": 100})
    # classify(periods=10) and bifurcation(transient_periods=5) ran, the keywords unread.
    with pytest.raises(ValueError, match="^periods: classify\\(\\) does not read"):
        gapchain.classify(MIRROR_PAIR, periods=10)
    with pytest.raises(ValueError, match="^step: regime_map\\(\\) does not read"):
        gapchain.regime_map(MIRROR_PAIR, e_r=[0.5], f_r=[1.2], step=0.001)
    with pytest.raises(ValueError, match="^transient_periods: bifurcation\\(\\) does not read"):
        gapchain.bifurcation(MIRROR_PAIR, from_=1.2, to=1.3, steps=2, transient_periods=5)
    # The dense limit is modes()' own keyword, and its refusal names it (it named
    # max_dense_bodies and said "raise the limit", which modes() had no argument for).
    with pytest.raises(ValueError, match="^max_dense: the dense solver for Nm = 60 .*raise max_dense"):
        gapchain.modes(60, 100, max_dense=50)
    assert gapchain.modes(60, 100, max_dense=60)["frequency"].shape == (60,)
    # A dict sets its members: the clearance's scatter was taken and ignored (helper-85).
    with pytest.raises(ValueError, match="^model.scatter.clearance: modes\\(\\) does not read"):
        gapchain.modes(5, 100, **{"model.scatter": {"clearance": 0.5, "seed": 3}})
    assert gapchain.classify(MIRROR_PAIR, scheme="rk4", transient=10, record=20)["scheme"] == "rk4"
    # So do the once-through runs, the searches and a simulate() without its trajectory, as
    # the tools refuse the --set (each of these ran, its result unchanged).
    with pytest.raises(ValueError, match="^steady_state: lyapunov\\(\\) does not read"):
        gapchain.lyapunov(MIRROR_PAIR, periods=30, steady_state=False)
    with pytest.raises(ValueError, match="^accuracy_mode: spectrum\\(\\) does not read"):
        gapchain.spectrum(MIRROR_PAIR, accuracy_mode="strict")
    with pytest.raises(ValueError, match="^trajectory_every: poincare\\(\\) does not read"):
        gapchain.poincare(MIRROR_PAIR, trajectory_every=3)

    with pytest.raises(ValueError, match="^estimate_error: attractors\\(\\) does not read"):
        gapchain.attractors(MIRROR_PAIR, samples=2, estimate_error=False)
    with pytest.raises(ValueError, match="^trajectory_every: simulate\\(\\) does not read"):
        gapchain.simulate(MIRROR_PAIR, periods=20, trajectory_every=5)
    assert gapchain.lyapunov(MIRROR_PAIR, periods=30, tolerance=1e-5)["status"] == "completed"
    # run.max_work is read: the refusal names it and the value given.
    with pytest.raises(ValueError, match="^run.max_work: .* above run.max_work = 10:"):
        gapchain.orbit(MIRROR_PAIR, max_work=10)
    with pytest.raises(ValueError, match="^run.max_work: .* above run.max_work = 10:"):
        gapchain.continuation(MIRROR_PAIR, from_=1.2, to=1.21, max_work=10)


def test_poincare_says_whether_the_record_repeats():
    # The mirror pair's runs settle on one of its two period-1 orbits (MODEL.md section 5); a
    # recorded t does not count against the repeat.
    assert gapchain.poincare(MIRROR_PAIR, record=["t", "u1", "v1"], error=False)[
        "repeats_every"] == 1
    # Nor do t and an event's trigger alone: they read period 1 on a chaotic record (helper-89).
    assert gapchain.poincare(MIRROR_PAIR, section="event", trigger="u1", level=0.0,
                             record=["t", "u1"], error=False)["repeats_every"] is None


def test_a_missing_required_argument_is_named():
    # pybind11 said "incompatible function arguments", naming nothing.
    with pytest.raises(TypeError, match="^basin_fractions\\(\\): missing required arguments: "
                                        "from_, to, steps$"):
        gapchain.basin_fractions(Nm=3, samples=3)
    with pytest.raises(TypeError, match="^basin_fractions\\(\\): missing required argument: "
                                        "steps$"):
        gapchain.basin_fractions(Nm=3, samples=3, from_=1.0, to=1.1)


def test_a_non_string_key_in_a_scene_dict_is_named():
    with pytest.raises(ValueError, match=r"^model: keys must be strings, got \('a',\) \(tuple\)"):
        gapchain.simulate({"model": {("a",): 1}}, periods=50)


def test_modes_refuse_run_keywords_and_the_shooting_names_its_schemes():
    # modes(periods=5) was taken and ignored, as gapchain-modes --set run.periods refuses.
    with pytest.raises(ValueError, match="^periods: modes\\(\\) does not read"):
        gapchain.modes(3, 60, periods=5)
    # The message listed auto and central_difference, which the search then refused.
    for name in ("RK4", "auto", "central_difference"):
        with pytest.raises(ValueError, match="^scheme: must be one of exact, rk4, rkf45, rk8pd"):
            gapchain.orbit(MIRROR_PAIR, scheme=name)


def test_analyses_of_the_five_reduced_numbers_refuse_other_rows():
    # bifurcation(), classify(), regime_map() and continuation() read the scene's five reduced
    # numbers only: a Hertz law, model arrays or a seismic record were run as the paper's row.
    fig13 = next(p for p in SCENES if p.endswith("fig13.json"))
    calls = {"bifurcation": lambda s, k: gapchain.bifurcation(s, from_=3, to=3.01, steps=2, **k),
             "classify": lambda s, k: gapchain.classify(s, **k),
             "regime_map": lambda s, k: gapchain.regime_map(s, e_r=[0.1], f_r=[1.0], **k),
             "continuation": lambda s, k: gapchain.continuation(s, from_=3, to=3.05, **k)}
    for name, call in calls.items():
        with pytest.raises(ValueError, match=f"^model.contact_law: {name}\\(\\) takes the paper"):
            call(fig13, {"model.contact_law": "hertz"})
        with pytest.raises(ValueError, match=f"^model.mass: {name}\\(\\)"):
            call(fig13, {"model.mass": [1, 2, 1, 1, 1]})
    seismic = next(p for p in SCENES if p.endswith("table4-experiment-seismic.json"))
    with pytest.raises(ValueError, match="^excitation.type: continuation\\(\\) needs harmonic"):
        gapchain.continuation(seismic, param="eps", from_=0.1, to=0.11)
    with pytest.raises(ValueError, match="^excitation.type: orbit\\(\\) needs harmonic forcing"):
        gapchain.orbit(seismic)


def test_line_limits_are_the_tools_limits():
    # The library's ranges were wider than the CLI's (steps up to 1e5 against 1e4, an arclength
    # step down to 0 against 1e-6), and a line from = to with several steps searched one point
    # again and again.
    fig13 = next(p for p in SCENES if p.endswith("fig13.json"))
    with pytest.raises(ValueError, match=r"^step: must be a finite number in \[1e-06, 1\]"):
        gapchain.continuation(fig13, from_=3, to=3.05, step=1e-9)
    with pytest.raises(ValueError, match=r"^steps: must be an integer in \[1, 10000\]"):
        gapchain.basin_fractions(fig13, param="f_r", from_=3, to=3.1, steps=20000, samples=2)
    with pytest.raises(ValueError, match="^steps: from = to"):
        gapchain.basin_fractions(fig13, param="f_r", from_=3, to=3, steps=3, samples=2)


def test_spectrum_default_segment_fits_a_shipped_scene():
    # A fixed 4096-sample segment was refused on every shipped scene (3201 samples recorded).
    scene = os.path.join(os.environ.get("GAPCHAIN_SCENES", ""), "fig13.json")
    r = gapchain.spectrum(scene)
    assert r["segment"] == 1920 and r["segments"] == 2  # 60 whole periods
    assert r["segment_periods"] == 60 and r["whole_periods"]
    assert r["df"] == pytest.approx(r["sample_rate"] / 1920)
    # At 32 samples a period u1 of Fig 13's row folds back almost nothing, its contact force
    # (a short pulse) far more; at 8 a period the force's spectrum is mostly folded.
    assert 0 <= r["aliased_share"] < 1e-6
    assert 0 <= r["broadband_share_error"] < 1e-3  # two segments of a periodic row
    assert gapchain.spectrum(scene, variable="F1")["aliased_share"] > 1e-4
    assert gapchain.spectrum(scene, variable="F1", samples_per_period=8)["aliased_share"] > 1e-2
    with pytest.raises(ValueError, match="^segment: must be 0 .* got 8$"):
        gapchain.spectrum(scene, segment=8)


def test_text_that_is_not_utf8_is_refused_naming_where(tmp_path):
    # An ill-formed byte in a scene file: the library's message quotes it escaped (it raised
    # ValueError() with no message); a lone surrogate, as os.fsdecode makes of an undecodable
    # file name, in a path, keyword or scene value (pybind11 raised RuntimeError).
    bad = tmp_path / "bad.json"
    bad.write_bytes(b'{"model": {"Nm": 2}, "run": {"periods": 50}, "x": "\xff"}')
    with pytest.raises(ValueError, match=r"ill-formed UTF-8 byte; last read: '\"\\xFF'"):
        gapchain.simulate(str(bad))
    with pytest.raises(ValueError, match="scene: must be valid UTF-8 text"):
        gapchain.simulate(str(tmp_path / "\udcff.json"))
    with pytest.raises(ValueError, match="keyword .*: must be valid UTF-8 text"):
        gapchain.simulate(**{"run.sch\udcff": 1})
    with pytest.raises(ValueError, match="model.contact_law: must be valid UTF-8 text"):
        gapchain.simulate({"model": {"contact_law": "h\udcff"}})


def test_a_trajectory_or_sweep_past_memory_is_refused_before_running():
    start = time.monotonic()
    with pytest.raises(ValueError, match="output.trajectory_every: the trajectory would hold"):
        gapchain.simulate(Nm=3, fc=100, e_r=0.2, f_r=1.3, trajectory=True, periods=10**6,
                          steady_state=False)
    with pytest.raises(ValueError, match="study: 10000000 points; sweep\\(\\) keeps every row"):
        gapchain.sweep({"parameters": {"f_r": {"lin": [0.5, 2, 10000]},
                                       "e_r": {"lin": [0, 1, 1000]}}})
    assert time.monotonic() - start < 5.0  # refused up front, not after running
    r = gapchain.simulate(Nm=3, fc=100, e_r=0.2, f_r=1.3, trajectory=True, periods=50,
                          steady_state=False, trajectory_every=10)
    assert r["trajectory"]["state"].shape[1] == 6


def test_modes_refuses_the_forcing_the_start_the_damping_and_the_clearances():
    # eps=7 and e_r=9 were taken and the modes returned unchanged.
    for key in ("f_r", "initial.u", "eps", "e_r", "model.contact_damping"):
        with pytest.raises(ValueError, match=key + ": modes\\(\\) does not read it"):
            gapchain.modes(5, 100, **{key: 2})
    # A Hertz row's modes were the linear row's.
    with pytest.raises(ValueError, match="^model.contact_law: the linear chain's modes need"):
        gapchain.modes(5, 100, **{"model.contact_law": "hertz"})


def test_a_non_finite_number_or_an_empty_key_part_is_named_as_such():
    with pytest.raises(ValueError, match="model.fc: must be a finite number in .*, got inf"):
        gapchain.simulate({"model": {"fc": np.float32("inf")}})
    with pytest.raises(ValueError, match="model.eps: must be a finite number in .*, got nan"):
        gapchain.simulate({"model": {"eps": float("nan")}})
    for key in ("model.", ".fc"):  # was "--set: expected section.key=value", a CLI message
        with pytest.raises(ValueError, match="^" + key + ": unknown key; a scene key is"):
            gapchain.simulate(**{key: 1})


def test_a_sweep_over_Nm_pads_per_body_with_nan():
    # Rows were read to the first row's length: the Nm = 1 row came back as garbage.
    s = gapchain.sweep({"scene": {"model": {"fc": 100, "e_r": 0.1}, "excitation": {"f_r": 1.3},
                                  "run": {"periods": 200}},
                        "parameters": {"model.Nm": [3, 1]}, "keep": ["per_body"]}, threads=1)
    one = gapchain.simulate(Nm=1, fc=100, e_r=0.1, f_r=1.3, periods=200)
    assert s["per_body"].shape == (2, 3, 2)
    assert s["per_body"][1, 0].tolist() == one["per_body"][0].tolist()
    assert np.all(np.isnan(s["per_body"][1, 1:])) and np.all(np.isnan(s["per_body_error"][1, 1:]))


def test_classify_gives_the_broadband_share_error():
    # Fig 13's row at f_r = 3.3 is chaotic: its share (0.037) is read, with the segments'
    # spread plus the aliased share as its error; a map gives the same field per cell.
    scene = os.path.join(os.environ.get("GAPCHAIN_SCENES", ""), "fig13.json")
    r = gapchain.classify(scene, **{"excitation.f_r": 3.3})
    assert r["regime"] == "chaotic"
    assert 0 < r["broadband_share_error"] < r["broadband_share"] / 5
    m = gapchain.regime_map(scene, e_r=[0.06], f_r=[3.0, 3.3], threads=1)
    assert m["broadband_share_error"].shape == (1, 2)
    assert m["broadband_share_error"][0, 0] == 0  # settled: not read
    assert m["broadband_share_error"][0, 1] == pytest.approx(r["broadband_share_error"])


def test_classify_twin_says_when_the_label_depends_on_the_start():
    # A chaotic transient that outlasts the default record (Nm 6, from u_1 = 6e-6: it settles on
    # a period-1 orbit after about 400 periods): the twin from a start moved by 1e-8 settles.
    row = {"Nm": 6, "fc": 324.45, "eps": 0.2399, "e_r": 0.2086, "f_r": 2.131,
           "initial.u": [6e-6, 0, 0, 0, 0, 0]}
    r = gapchain.classify(**row)
    assert r["regime"] == "chaotic" and r["twin_checked"] and r["start_dependent"]
    assert r["twin"]["regime"] == "periodic" and r["twin"]["period"] == 1
    assert r["twin"]["status"] == "completed" and r["twin"]["newton_confirmed"]
    assert r["F_m_error"] >= abs(r["F_m"] - r["twin"]["F_m"])
    alone = gapchain.classify(twin=False, **row)
    assert not alone["twin_checked"] and alone["start_dependent"] is None and "twin" not in alone
    # A transient that ends within the record: the label is the steady state's.
    settled = gapchain.classify(Nm=2, fc=15.70, eps=0.287, e_r=0.0615, f_r=3.642)
    assert settled["regime"] == "periodic" and settled["settled_in_record"]
    assert settled["twin_checked"] is False and "twin" not in settled
    ms = gapchain.regime_map(Nm=2, fc=15.70, eps=0.287, e_r=[0.0615], f_r=[3.642], threads=1)
    assert ms["settled_in_record"].tolist() == [[True]] and ms["period"].tolist() == [[2]]
    m = gapchain.regime_map(e_r=[0.2086], f_r=[2.131, 1.0], threads=1,
                            **{k: v for k, v in row.items() if k not in ("e_r", "f_r")})
    assert m["start_dependent"].tolist() == [[True, False]]
    assert m["twin_checked"].tolist() == [[True, False]]


def test_an_integer_beyond_its_cpp_type_names_the_keys_own_range():
    # steps=2**33 said "must be an integer in [-2**31, 2**31)", the C++ type's range, not the
    # key's. Every integer argument of every function is asked, at both signs, so that a new
    # one whose range reaches the type's limit (the clamped retry would then run) fails here.
    required = {"basin_fractions": dict(param="f_r", from_=1.0, to=1.1, steps=2),
                "regime_map": dict(e_r=[0.1], f_r=[1.0]), "sweep": dict(study={"parameters": {"fc": [1]}}),
                "attractors": dict(grid=("u1", "v1")), "simulate": dict(attractors=2),
                "classify": dict(attractors=2)}
    asked = 0
    for name in gapchain._FUNCTIONS:
        compiled = getattr(gapchain._gapchain, name)
        try:
            compiled(*([None] * 64))
        except TypeError as error:
            parameters = gapchain._signature(str(error))[0]
        for parameter, kind in parameters:
            if kind not in ("int", "Optional[int]") or parameter == "seed":
                continue
            for value in (2 ** 40, -2 ** 40, 2 ** 70):
                kwargs = dict(required.get(name, {}), **{parameter: value})
                with pytest.raises(ValueError) as raised:
                    getattr(gapchain, name)(**kwargs)
                message = str(raised.value)
                assert message.startswith(parameter + ":"), (name, message)
                assert "2**31" not in message and "2**63" not in message, (name, message)
                assert message.endswith("got %d" % value), (name, message)
                asked += 1
    assert asked == 3 * 35  # 35 integer arguments in 12 functions (modes' max_dense the last)
    assert str(pytest.raises(ValueError, gapchain.bifurcation, steps=2 ** 33).value) == \
        "steps: must be an integer in [1, 10000000], got 8589934592"
    # Two at once: the message names one, with its own value (it took the other's).
    assert str(pytest.raises(ValueError, gapchain.bifurcation, steps=2 ** 40,
                             transient=2 ** 50).value) == \
        "steps: must be an integer in [1, 10000000], got %d" % 2 ** 40
    # A diagram's variable is a state variable: t is neither taken nor offered.
    with pytest.raises(ValueError, match=r'^variable: must be a state variable, u1\.\.u5, .*got "x9"'):
        gapchain.bifurcation(variable="x9")


def test_a_keyword_of_the_other_kind_of_section_is_refused_and_messages_name_the_argument():
    # poincare(level=0.3) on a stroboscopic section returned the section without it, as
    # gapchain-poincare refuses --level there.
    for kwargs, message in [(dict(level=0.3), r'^level: applies to section="event" only'),
                            (dict(trigger="u3"), r'^trigger: applies to section="event"'),
                            (dict(direction="down"), r'^direction: applies to section="event"'),
                            (dict(section="event", phase=0.7),
                             r'^phase: applies to section="stroboscopic" only')]:
        with pytest.raises(ValueError, match=message):
            gapchain.poincare(MIRROR_PAIR, **kwargs)
    event = gapchain.poincare(MIRROR_PAIR, section="event", level=0.0, direction="up", **SHORT)
    assert np.array_equal(event["t"], gapchain.poincare(MIRROR_PAIR, section="event", **SHORT)["t"])
    # The scheme and step that ran, not "auto" (section.json's, a reviewer's probe, helper-77).
    assert event["scheme"] in ("rk4", "exact", "rkf45", "rk8pd", "central_difference")
    stepped = gapchain.poincare(MIRROR_PAIR, scheme="rk4", step=0.001, **SHORT)
    assert stepped["scheme"] == "rk4" and 0.0009 < stepped["step"] <= 0.001
    # The argument, not the library's option behind it (section.level, model.e_r) ...
    with pytest.raises(ValueError, match=r"^level: must be a finite number"):
        gapchain.poincare(MIRROR_PAIR, section="event", level=math.nan)
    with pytest.raises(ValueError, match=r"^record: u1 given twice"):
        gapchain.poincare(MIRROR_PAIR, record=["u1", "u1"])
    with pytest.raises(ValueError, match=r"^e_r: must be a finite number in \[0, 1000000\], got nan"):
        gapchain.regime_map(MIRROR_PAIR, e_r=[math.nan], f_r=[1.0])
    with pytest.raises(ValueError, match=r"^f_r: must be a finite number in \(0, 10000\]"):
        gapchain.regime_map(MIRROR_PAIR, e_r=[0.1], f_r=[-1.0])
    # ... but the scene's own key where the scene is wrong.
    with pytest.raises(ValueError, match=r"^model.e_r: must be"):
        gapchain.regime_map({"model": {"e_r": -1}}, e_r=[0.1], f_r=[1.0])
    # One line, whatever the user's text holds: a newline split the message.
    for function, kwargs in [(gapchain.spectrum, dict(variable="u\n1")),
                             (gapchain.simulate, dict(scene="/tmp/no\nsuch.json")),
                             (gapchain.bifurcation, dict(param="f\n_r")),
                             (gapchain.poincare, dict(record=["u1", "v\n1"]))]:
        with pytest.raises(ValueError) as raised:
            function(**kwargs)
        assert "\n" not in str(raised.value) and "\\n" in str(raised.value)
