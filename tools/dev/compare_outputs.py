#!/usr/bin/env python3
"""Compares two output folders of tools/dev/regression_outputs.sh, file by file.

JSON files are compared value by value and CSV files cell by cell, except for wall times
(keys and columns whose name contains "wall_time" or "time_s", and the "elapsed" lines of
logs), thread counts, and paths that name the output folder. PNG files are not compared.
Prints each difference and exits 1 if any.

    python3 tools/dev/compare_outputs.py BEFORE AFTER
"""
import csv
import json
import pathlib
import re
import sys

IGNORED = re.compile(r"wall_time|time_s$|median_time|seconds|threads_used|^written$|^study$|^built$")


def strip(value, root):
    if isinstance(value, dict):
        return {k: strip(v, root) for k, v in value.items() if not IGNORED.search(k)}
    if isinstance(value, list):
        return [strip(v, root) for v in value]
    if isinstance(value, str):
        return value.replace(root, "<out>")
    return value


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return rows
    keep = [i for i, name in enumerate(rows[0]) if not IGNORED.search(name)]
    body = [[r[i] for i in keep if i < len(r)] for r in rows]
    # Sweep rows arrive in completion order: compare them sorted by index.
    return [body[0]] + sorted(body[1:])


def read_log(path, root):
    lines = []
    for line in path.read_text(errors="replace").splitlines():
        line = line.replace(root, "<out>")
        # Timing lines and the accuracy table (its numbers are compared in its CSV) vary.
        if re.search(r"\bs\b|/s\b|wall|time|median", line) or path.name == "accuracy.log":
            continue
        lines.append(line)
    return lines


def main(before, after):
    a_root, b_root = pathlib.Path(before), pathlib.Path(after)
    names = sorted({p.relative_to(a_root) for p in a_root.rglob("*") if p.is_file()}
                   | {p.relative_to(b_root) for p in b_root.rglob("*") if p.is_file()})
    differences = 0
    for name in names:
        if name.suffix in (".png", ".err") or name.name.endswith(".lock"):
            continue
        a, b = a_root / name, b_root / name
        if not a.exists() or not b.exists():
            print(f"{name}: only in {'after' if b.exists() else 'before'}")
            differences += 1
            continue
        if name.suffix == ".json":
            same = strip(json.loads(a.read_text()), str(a_root)) == strip(
                json.loads(b.read_text()), str(b_root))
        elif name.suffix == ".csv":
            same = read_csv(a) == read_csv(b)
        else:
            same = read_log(a, str(a_root)) == read_log(b, str(b_root))
        if not same:
            print(f"{name}: differs")
            differences += 1
    print(f"{len(names)} files, {differences} differ")
    return 1 if differences else 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
