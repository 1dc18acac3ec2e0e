#!/usr/bin/env python3
"""Does gapchain-sim's error bar cover an independent answer? A random draw over the paper's
ranges (Nm 2-10, fc 60-2000, eps 0.05-0.5, e_r 0-0.4, f_r 0.3-3; 400 periods), each point run as
a user would (default scheme and tolerance), then again with rk8pd at tolerance 1e-9 on the same
recorded window (run.transient_periods as the default run used). For the periodic points with
contact it counts how often |F_m - F_m(rk8pd)| and |F_m_orbit - F_m_orbit(rk8pd)| stay within
F_m_error, how often the latter stays within the orbit's own bar F_m_orbit_error (where the
build reports one and rk8pd settled with the same period), how many took their maximum in the transient, and how many the tool calls
multistable (and why). Prints a summary and, with --list, one line per point.

    python3 tools/dev/error_coverage.py build/bin/gapchain-sim [--points 300] [--list]
        [--ranges paper-scale]   (Nm 1-10, fc 1-2000 log-uniform, eps 0.1-0.5, e_r 0-6, f_r 0.1-5)
"""
import argparse
import concurrent.futures
import json
import math
import os
import random
import subprocess
import tempfile


def draw(seed, ranges):
    rnd = random.Random(seed)
    if ranges == "paper-scale":
        # The paper-scale study's ranges (data/studies/paper-scale.json), drawn continuously;
        # soft contacts (fc down to 1) and wide clearances included. Rows of up to 10 bodies.
        return {"model": {"Nm": rnd.choice([1, 2, 3, 5, 10]),
                          "fc": round(10 ** rnd.uniform(0, math.log10(2000)), 4),
                          "eps": round(rnd.uniform(0.1, 0.5), 4),
                          "e_r": round(rnd.uniform(0, 0.35) if rnd.random() < 0.5
                                       else rnd.uniform(0.35, 6), 4)},
                "excitation": {"f_r": round(rnd.uniform(0.1, 5), 4)},
                "run": {"periods": 400}}
    return {"model": {"Nm": rnd.randint(2, 10), "fc": round(rnd.uniform(60, 2000), 3),
                      "eps": round(rnd.uniform(0.05, 0.5), 3),
                      "e_r": round(rnd.uniform(0, 0.4), 3)},
            "excitation": {"f_r": round(rnd.uniform(0.3, 3), 3)},
            "run": {"periods": 400}}


def simulate(binary, scene, sets, workdir):
    with tempfile.NamedTemporaryFile("w", suffix=".json", dir=workdir, delete=False) as f:
        json.dump(scene, f)
    out = f.name + ".out.json"
    cmd = [binary, f.name, "--out", out]
    for s in sets:
        cmd += ["--set", s]
    done = subprocess.run(cmd, capture_output=True, text=True)
    result = json.load(open(out)) if done.returncode == 0 else None
    for path in (f.name, out):
        if os.path.exists(path):
            os.remove(path)
    return result


def point(binary, seed, workdir, ranges):
    scene = draw(seed, ranges)
    run = simulate(binary, scene, [], workdir)
    if not run or run["status"] != "steady_state" or run["F_m"] <= 0.0:
        return None
    ref = simulate(binary, scene, ["run.scheme=rk8pd", "run.tolerance=1e-9",
                                   f"run.transient_periods={run['transient_periods_used']}",
                                   "run.multistability_check=false"], workdir)
    return {"seed": seed, "scene": scene, "run": run, "ref": ref}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("binary", help="path to gapchain-sim")
    parser.add_argument("--points", type=int, default=300, help="points drawn (seeds 1..N)")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--list", action="store_true", help="one line per periodic point")
    parser.add_argument("--ranges", choices=["paper", "paper-scale"], default="paper",
                        help="paper: the ranges above; paper-scale: Nm 1-10, fc 1-2000 "
                             "(log-uniform), eps 0.1-0.5, e_r 0-6, f_r 0.1-5")
    args = parser.parse_args()
    workdir = tempfile.mkdtemp(prefix="gapchain-coverage-")
    with concurrent.futures.ThreadPoolExecutor(args.threads) as pool:
        rows = [r for r in pool.map(lambda s: point(args.binary, s, workdir, args.ranges),
                                    range(1, args.points + 1)) if r]
    os.rmdir(workdir)
    counts = {"window": 0, "orbit": 0, "orbit_n": 0, "transient": 0, "multistable": 0,
              "twin": 0, "elsewhere": 0, "own": 0, "own_n": 0, "own_none": 0, "own_other": 0}
    worst_orbit = 0.0
    own_ratios = []
    for r in rows:
        run, ref = r["run"], r["ref"]
        err = run["F_m_error"] or 0.0
        window_gap = abs(run["F_m"] - ref["F_m"])
        counts["window"] += window_gap <= err
        if run.get("F_m_orbit") is not None and ref.get("F_m_orbit") is not None:
            orbit_gap = abs(run["F_m_orbit"] - ref["F_m_orbit"])
            counts["orbit_n"] += 1
            counts["orbit"] += orbit_gap <= err
            worst_orbit = max(worst_orbit, orbit_gap / err if err > 0 else float("inf"))
            own = run.get("F_m_orbit_error")
            if run["steady_state_period"] != ref["steady_state_period"]:
                counts["own_other"] += 1  # rk8pd settled on another orbit: not this one's error
            elif own is None:
                counts["own_none"] += 1
            else:
                counts["own_n"] += 1
                counts["own"] += orbit_gap <= own
                own_ratios.append(orbit_gap / own if own > 0
                                  else (0.0 if orbit_gap == 0.0 else float("inf")))
        counts["transient"] += run["maximum_in_transient"]
        counts["multistable"] += run["multistable"]
        counts["twin"] += run["multistable"] and run.get("F_m_twin") is not None
        counts["elsewhere"] += bool(run.get("comparison_ended_elsewhere"))
        if args.list:
            m = r["scene"]["model"]
            print(f"seed {r['seed']:4d} Nm {m['Nm']:2d} fc {m['fc']:8.3f} eps {m['eps']:.3f} "
                  f"e_r {m['e_r']:.3f} f_r {r['scene']['excitation']['f_r']:.3f}: "
                  f"F_m {run['F_m']:.6g} +- {err:.2g}, rk8pd {ref['F_m']:.6g}; orbit "
                  f"{run.get('F_m_orbit')} +- {run.get('F_m_orbit_error')}, "
                  f"rk8pd {ref.get('F_m_orbit')}; "
                  f"transient {run['maximum_in_transient']}, multistable {run['multistable']}, "
                  f"comparison elsewhere {run.get('comparison_ended_elsewhere')}")
    n = len(rows)
    print(f"{args.points} points drawn, {n} periodic with contact")
    print(f"  window maximum within F_m_error of rk8pd's (same window): {counts['window']}/{n}")
    print(f"  orbit maximum within F_m_error of rk8pd's orbit: {counts['orbit']}/"
          f"{counts['orbit_n']} (largest gap / F_m_error: {worst_orbit:.2f})")
    if counts["own_n"]:
        own_ratios.sort()
        print(f"  orbit maximum within its own F_m_orbit_error: {counts['own']}/{counts['own_n']}"
              f" ({counts['own_none']} not estimated, {counts['own_other']} where rk8pd settled "
              f"with another period; gap / bar: median "
              f"{own_ratios[len(own_ratios) // 2]:.2g}, largest {own_ratios[-1]:.2f})")
    print(f"  maximum in the transient: {counts['transient']}/{n}")
    print(f"  multistable: {counts['multistable']}/{n} ({counts['twin']} with a twin run, "
          f"{counts['elsewhere']} whose comparison run ended elsewhere)")


if __name__ == "__main__":
    main()
