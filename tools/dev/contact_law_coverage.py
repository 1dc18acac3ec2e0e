#!/usr/bin/env python3
"""Does the default run's F_m_error cover the error under a nonlinear contact law?

Usage: python3 tools/dev/contact_law_coverage.py GAPCHAIN_SIM SEED LAW COUNT

Draws COUNT random rows (Nm 1-5, fc 30-1000, eps 0.05-0.5, e_r 0-0.4, f_r 0.4-2.5, and for
hunt_crossley alpha 0.01-0.5) with the seeded draw SEED and the contact law LAW (hertz or
hunt_crossley), runs each as a user would (300 periods, 100 discarded, rk4 at the default
tolerance) and again on rk8pd at 1e-11 without a steady-state stop over the same window, and
prints for each row the default F_m +- F_m_error, the reference and |difference| / F_m_error.
Rows without contact are skipped; a non-periodic row's bar is a sampling spread (one draw of the
window), so its ratio says less (docs/accuracy.md).
"""
import json
import os
import random
import subprocess
import sys
import tempfile


def run(sim, scene_path, out_path, *sets):
    args = [sim, scene_path, "--out", out_path]
    for s in sets:
        args += ["--set", s]
    subprocess.run(args, capture_output=True, check=True)
    with open(out_path) as f:
        return json.load(f)


def main():
    if len(sys.argv) != 5 or sys.argv[3] not in ("hertz", "hunt_crossley"):
        sys.exit(__doc__.strip().splitlines()[2])
    sim, seed, law, count = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
    rng = random.Random(seed)
    missed = rows = 0
    with tempfile.TemporaryDirectory() as tmp:
        scene_path = os.path.join(tmp, "scene.json")
        for i in range(count):
            model = {"Nm": rng.choice([1, 2, 3, 5]), "fc": 10 ** rng.uniform(1.5, 3),
                     "eps": rng.uniform(0.05, 0.5), "e_r": rng.uniform(0, 0.4),
                     "contact_law": law}
            f_r = rng.uniform(0.4, 2.5)
            if law == "hunt_crossley":
                model["contact_damping"] = rng.uniform(0.01, 0.5)
            with open(scene_path, "w") as f:
                json.dump({"model": model, "excitation": {"f_r": f_r},
                           "run": {"periods": 300, "transient_periods": 100}}, f)
            r = run(sim, scene_path, os.path.join(tmp, "default.json"))
            ref = run(sim, scene_path, os.path.join(tmp, "reference.json"), "run.scheme=rk8pd",
                      "run.tolerance=1e-11", "run.estimate_error=false",
                      "run.multistability_check=false", "run.steady_state=false")
            if r["F_m"] == 0 and ref["F_m"] == 0:
                continue
            rows += 1
            error = r["F_m_error"]
            gap = abs(r["F_m"] - ref["F_m"])
            covered = error is not None and gap <= error
            missed += not covered
            ratio = gap / error if error else float("inf")
            print(f"{i} Nm={model['Nm']} fc={model['fc']:.1f} eps={model['eps']:.3f} "
                  f"e_r={model['e_r']:.3f} f_r={f_r:.3f}: {r['F_m']:.8f} +- {error} "
                  f"ref {ref['F_m']:.8f} ratio {ratio:.2f} period={r['steady_state_period']} "
                  f"{'ok' if covered else 'NOT COVERED'}", flush=True)
    print(f"not covered: {missed} of {rows}")


if __name__ == "__main__":
    main()
