#!/usr/bin/env python3
"""Every run of equal period in a gapchain-bifurcation summary.csv, in order of the value.

Usage: python3 docs/plot/period_windows.py SUMMARY_CSV [DIRECTION]
Prints "from - to: period k (n values)" for each run of consecutive values with the same
period column (0: no period up to 16 within the record), for one direction ("up" by default).
"""
import csv
import sys


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__.strip().splitlines()[2])
    direction = sys.argv[2] if len(sys.argv) == 3 else "up"
    with open(sys.argv[1], newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["direction"] == direction]
    if not rows:
        sys.exit(f"{sys.argv[1]}: no rows with direction {direction}")
    runs = []
    for r in rows:
        value, period = float(r["value"]), int(r["period"])
        if runs and runs[-1][2] == period:
            runs[-1][1] = value
            runs[-1][3] += 1
        else:
            runs.append([value, value, period, 1])
    for low, high, period, count in runs:
        what = f"period {period}" if period > 0 else "not periodic"
        span = f"{low:.4f}" if count == 1 else f"{low:.4f} - {high:.4f}"
        print(f"{span}: {what} ({count} value{'s' if count > 1 else ''})")


if __name__ == "__main__":
    main()
