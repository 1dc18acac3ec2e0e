#!/usr/bin/env python3
"""Tables 2 and 3 of the paper from a gapchain-sweep CSV of data/studies/tables-2-3.json:
the maximum F_m over the smooth (e_r > 0.3) and low-clearance (e_r < 0.3) regions, per eps,
against 1/(2 eps) (eq 25) and pi / (2 eps sqrt(4.935)) (eq 37).
Usage: python3 docs/plot/tables_2_3.py RESULTS.csv"""
import csv
import math
import sys

rows = list(csv.DictReader(open(sys.argv[1])))
paper_smooth = {0.1: 3.75, 0.2: 2.46, 0.3: 1.45, 0.5: 0.93}
paper_chaotic = {0.1: 7.02, 0.2: 3.88, 0.3: 2.65, 0.5: 1.86}
print(f"{len(rows)} points")
print("| eps | max F_m, e_r > 0.3 (where: fc, e_r, f_r) | same, periodic points only | paper Table 2 | "
      "1/(2 eps) | max F_m, e_r < 0.3 (where) | paper Table 3 | pi/(2 eps sqrt(4.935)) |")
print("| --- | --- | --- | --- | --- | --- | --- | --- |")
for eps in sorted(paper_smooth):
    mine = [r for r in rows if abs(float(r["eps"]) - eps) < 1e-12]
    def best(region, periodic_only=False):
        pts = [r for r in mine if region(float(r["e_r"])) and
               (not periodic_only or r["steady_state_period"] != "")]
        if not pts:
            return "-"
        r = max(pts, key=lambda r: float(r["F_m"]))
        return f"{float(r['F_m']):.3f} ({float(r['fc']):g}, {float(r['e_r']):g}, {float(r['f_r']):.2f})"
    print(f"| {eps} | {best(lambda e: e > 0.3)} | {best(lambda e: e > 0.3, True)} | "
          f"{paper_smooth[eps]} | {1 / (2 * eps):.3f} | "
          f"{best(lambda e: e < 0.3)} | {paper_chaotic[eps]} | {math.pi / (2 * eps * math.sqrt(4.935)):.3f} |")
