#!/usr/bin/env python3
"""Where a gapchain-sweep study spent its time: points and core seconds per fc, split into
periodic (stopped at the steady state) and non-periodic rows. Needs "wall_time" in the study's
keep list. Usage: python3 docs/plot/study_time.py RESULTS.csv"""
import collections
import csv
import sys

points = collections.Counter()
seconds = collections.Counter()
for r in csv.DictReader(open(sys.argv[1])):
    kind = "periodic" if r["status"] == "steady_state" else "not periodic"
    points[(float(r["fc"]), kind)] += 1
    seconds[(float(r["fc"]), kind)] += float(r["wall_time_s"])
total = sum(seconds.values())
print(f"{sum(points.values())} points, {total:.0f} core seconds")
print("| fc | periodic points | their core s | non-periodic points | their core s | share of time |")
print("| --- | --- | --- | --- | --- | --- |")
for fc in sorted({fc for fc, _ in points}):
    p, n = (fc, "periodic"), (fc, "not periodic")
    share = (seconds[p] + seconds[n]) / total
    print(f"| {fc:g} | {points[p]} | {seconds[p]:.0f} | {points[n]} | {seconds[n]:.0f} | "
          f"{100 * share:.1f} % |")
for kind in ("periodic", "not periodic"):
    k_points = sum(v for (fc, k), v in points.items() if k == kind)
    k_seconds = sum(v for (fc, k), v in seconds.items() if k == kind)
    print(f"{kind}: {k_points} points, mean {k_seconds / max(k_points, 1):.4f} s, "
          f"{100 * k_seconds / total:.1f} % of the time")
