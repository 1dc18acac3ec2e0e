#!/usr/bin/env python3
"""Tables 2 and 3 of the paper from a gapchain-sweep CSV (data/studies/tables-2-3.json, or the
full data/studies/paper-scale.json): the maximum F_m over the smooth (e_r > 0.3) and
low-clearance (e_r < 0.3) regions, per eps, against 1/(2 eps) (eq 25) and
pi / (2 eps sqrt(4.935)) (eq 37); then the same maxima split by the number of bodies Nm.
Usage: python3 docs/plot/tables_2_3.py RESULTS.csv"""
import csv
import math
import sys

rows = list(csv.DictReader(open(sys.argv[1])))
paper_smooth = {0.1: 3.75, 0.2: 2.46, 0.3: 1.45, 0.5: 0.93}
paper_chaotic = {0.1: 7.02, 0.2: 3.88, 0.3: 2.65, 0.5: 1.86}


def smooth(e_r):
    return e_r > 0.3


def low_clearance(e_r):
    return e_r < 0.3


def largest(pts):
    return max(pts, key=lambda r: float(r["F_m"])) if pts else None


def where(r):
    if r is None:
        return "-"
    # An empty F_m_error: the study asked for no estimate (run.estimate_error false).
    error = f" +- {float(r['F_m_error']):.2g}" if r["F_m_error"] else ""
    return (f"{float(r['F_m']):.3f}{error} (Nm {r['Nm']}, fc {float(r['fc']):g}, "
            f"e_r {float(r['e_r']):.3g}, f_r {float(r['f_r']):.3g})")


def points(eps, region, nm=None, periodic_only=False):
    return [r for r in rows if abs(float(r["eps"]) - eps) < 1e-12 and region(float(r["e_r"]))
            and (nm is None or r["Nm"] == nm)
            and (not periodic_only or r["steady_state_period"] != "")]


print(f"{len(rows)} points")
print("| eps | max F_m, e_r > 0.3 | same, periodic points only | paper Table 2 | 1/(2 eps) "
      "| max F_m, e_r < 0.3 | paper Table 3 | pi/(2 eps sqrt(4.935)) |")
print("| --- | --- | --- | --- | --- | --- | --- | --- |")
for eps in sorted(paper_smooth):
    print(f"| {eps} | {where(largest(points(eps, smooth)))} "
          f"| {where(largest(points(eps, smooth, periodic_only=True)))} "
          f"| {paper_smooth[eps]} | {1 / (2 * eps):.3f} | {where(largest(points(eps, low_clearance)))} "
          f"| {paper_chaotic[eps]} | {math.pi / (2 * eps * math.sqrt(4.935)):.3f} |")

nms = sorted({r["Nm"] for r in rows}, key=int)
if len(nms) > 1:
    print()
    print("max F_m by Nm, smooth (e_r > 0.3) / low clearance (e_r < 0.3):")
    print("| eps | " + " | ".join(f"Nm = {n}" for n in nms) + " | paper | bounds |")
    print("| --- " * (len(nms) + 3) + "|")
    for eps in sorted(paper_smooth):
        cells = []
        for n in nms:
            s, c = largest(points(eps, smooth, n)), largest(points(eps, low_clearance, n))
            cells.append(f"{float(s['F_m']) if s else float('nan'):.2f} / "
                         f"{float(c['F_m']) if c else float('nan'):.2f}")
        print(f"| {eps} | " + " | ".join(cells) + f" | {paper_smooth[eps]} / {paper_chaotic[eps]} "
              f"| {1 / (2 * eps):.2f} / {math.pi / (2 * eps * math.sqrt(4.935)):.2f} |")
