#!/usr/bin/env python3
"""Does a non-settling point's F_m_error cover other starts' F_m?

For each point of a sweep CSV whose run did not settle (status "completed", wall time below
--max-seconds), runs gapchain.simulate as a user would (the defaults: auto, its error estimate
and multistability check), then --starts strict runs from starts u_1(0) = k 1e-7 (k = 0 ..
starts - 1; no error estimate, no twin). Prints, per point, the default answer, its bar, the
strict starts' mean and standard deviation, and how many of them lie within the bar of the
default answer; then the totals.

    python3 tools/dev/chaotic_coverage.py ps5.csv [--starts 5] [--max-seconds 2]
"""
import argparse
import csv
import statistics
import sys

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("csv", help="a gapchain-sweep CSV (paper-scale study)")
parser.add_argument("--starts", type=int, default=5, help="strict starts per point, >= 2")
parser.add_argument("--max-seconds", type=float, default=2.0,
                    help="skip points whose sweep run took longer, > 0")
parser.add_argument("--python", default="build/python", help="folder of the gapchain module")
args = parser.parse_args()
if args.starts < 2 or not args.max_seconds > 0:
    parser.error("--starts must be >= 2 and --max-seconds > 0")
sys.path.insert(0, args.python)
import gapchain  # noqa: E402

rows = [r for r in csv.DictReader(open(args.csv))
        if r["status"] == "completed" and float(r["wall_time_s"]) < args.max_seconds]
inside_all = inside_relaxed = total_relaxed = 0
for r in rows:
    Nm = int(r["Nm"])
    p = dict(Nm=Nm, fc=float(r["fc"]), eps=float(r["eps"]), e_r=float(r["e_r"]),
             f_r=float(r["f_r"]), periods=1000, tolerance=1e-4)
    base = gapchain.simulate(None, **p)
    values = []
    for k in range(args.starts):
        u = [0.0] * Nm
        u[0] = k * 1e-7
        values.append(gapchain.simulate(None, accuracy_mode="strict", estimate_error=False,
                                        multistability_check=False, **{"initial.u": u},
                                        **p)["F_m"])
    mean, sd = statistics.mean(values), statistics.stdev(values)
    inside = sum(abs(v - base["F_m"]) <= base["F_m_error"] for v in values)
    inside_all += inside
    if base["accuracy_mode_used"] == "relaxed":
        inside_relaxed += inside
        total_relaxed += args.starts
    print(r["index"], Nm, p["fc"], p["eps"], p["e_r"], p["f_r"],
          "mode %s F_m %.5f bar %.2e strict_mean %.5f sd %.2e inside %d/%d"
          % (base["accuracy_mode_used"], base["F_m"], base["F_m_error"], mean, sd, inside,
             args.starts), flush=True)
print("points %d: strict starts within the default answer's bar %d/%d (relaxed answers %d/%d)"
      % (len(rows), inside_all, args.starts * len(rows), inside_relaxed, total_relaxed))
