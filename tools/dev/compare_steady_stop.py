"""Two builds' gapchain-sim on the same random points of the paper-scale grid: steady-state
period, periods simulated, F_m and wall time (the steady-state stop's cost and answers).

Usage: python3 tools/dev/compare_steady_stop.py OLD_GAPCHAIN_SIM NEW_GAPCHAIN_SIM [POINTS] [SEED]
(run from the repository root; multistability check off, 1000 periods, tolerance 1e-4).
"""
import json
import random
import subprocess
import sys
import tempfile
import time


def run_all(binary, points, folder):
    results = []
    for p in points:
        scene = {"model": {k: p[k] for k in ("Nm", "fc", "eps", "e_r")},
                 "excitation": {"f_r": p["f_r"]},
                 "run": {"periods": 1000, "tolerance": 1e-4, "multistability_check": False}}
        path = f"{folder}/scene.json"
        with open(path, "w") as f:
            json.dump(scene, f)
        subprocess.run([binary, path, "--out", path + ".out"], check=True,
                       stdout=subprocess.DEVNULL)
        with open(path + ".out") as f:
            r = json.load(f)
        results.append((r["steady_state_period"], r["periods_simulated"], r["F_m"],
                        r["wall_time_s"]))
    return results


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    count = int(argv[3]) if len(argv) > 3 else 500
    seed = int(argv[4]) if len(argv) > 4 else 7
    with open("data/studies/paper-scale.json") as f:
        axes = json.load(f)["parameters"]
    rng = random.Random(seed)
    points = [{k: rng.choice(v) for k, v in axes.items()} for _ in range(count)]
    with tempfile.TemporaryDirectory() as folder:
        old = run_all(argv[1], points, folder)
        new = run_all(argv[2], points, folder)
    changed = [(points[i], a[0], b[0]) for i, (a, b) in enumerate(zip(old, new)) if a[0] != b[0]]
    print(f"{count} points (seed {seed}); steady period differs at {len(changed)}:")
    for p, a, b in changed:
        print(f"  {p}: {a} -> {b}")
    print("periods simulated old / new:", sum(a[1] for a in old), "/", sum(b[1] for b in new))
    print("F_m differs beyond 1e-9 relative at",
          sum(1 for a, b in zip(old, new) if abs(a[2] - b[2]) > 1e-9 * abs(a[2])), "points")
    print("wall time old / new [s]: %.2f / %.2f" % (sum(a[3] for a in old),
                                                     sum(b[3] for b in new)))


if __name__ == "__main__":
    start = time.time()
    main(sys.argv)
    print("(%.0f s)" % (time.time() - start))
