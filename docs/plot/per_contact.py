#!/usr/bin/env python3
"""Per-contact maxima from a gapchain-sweep CSV kept with "per_body" (body i: left|right maxima),
as rows "x,contact,F" for a gnuplot heat map: contact 0 is the left wall, Nm the right wall.
Usage: python3 docs/plot/per_contact.py RESULTS.csv XCOLUMN > OUT.dat"""
import csv
import sys

rows = sorted(csv.DictReader(open(sys.argv[1])), key=lambda r: float(r[sys.argv[2]]))
for r in rows:
    bodies = [tuple(map(float, b.split("|"))) for b in r["per_body"].split(";")]
    forces = [bodies[0][0]] + [right for _, right in bodies]
    for j, f in enumerate(forces):
        print(f"{r[sys.argv[2]]},{j},{f}")
    print()
