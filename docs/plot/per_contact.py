#!/usr/bin/env python3
"""Per-contact maxima from a gapchain-sweep CSV kept with "per_body" (body i: left|right maxima),
as rows "x,contact,F" for a gnuplot heat map: contact 0 is the left wall, Nm the right wall.
Optional KEY=VALUE arguments keep only the rows whose column KEY equals VALUE (as numbers),
e.g. fc=100 for one panel of a study over several fc.
Usage: python3 docs/plot/per_contact.py RESULTS.csv XCOLUMN [KEY=VALUE ...] > OUT.dat"""
import csv
import sys

filters = [arg.split("=", 1) for arg in sys.argv[3:]]
rows = [r for r in csv.DictReader(open(sys.argv[1]))
        if all(float(r[key]) == float(value) for key, value in filters)]
if not rows:
    sys.exit(f"per_contact.py: no row of {sys.argv[1]} matches {' '.join(sys.argv[3:])}")
rows.sort(key=lambda r: float(r[sys.argv[2]]))
for r in rows:
    bodies = [tuple(map(float, b.split("|"))) for b in r["per_body"].split(";")]
    forces = [bodies[0][0]] + [right for _, right in bodies]
    for j, f in enumerate(forces):
        print(f"{r[sys.argv[2]]},{j},{f}")
    print()
