"""Transient lifetimes from gapchain-attractors' starts.csv files.

Usage: python3 docs/plot/transient_lifetimes.py OUT.png [--fm F_m] LABEL DIR/starts.csv [LABEL CSV ...]

Left: the share of starts whose transient has not ended after n periods (log scale), with the
exponential that gapchain-attractors measured (the "transients" of attractors.json next to each
starts.csv): P = P0 exp(-(n - from_period) / lifetime) beyond the median length from_period,
P0 the share still in the transient there. Right, for the first file: each start's run F_m
(over its recorded window) against where its transient ended, with the attractor's F_m (--fm)
as a line. Prints the tool's lifetime per file.
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

def read_transients(starts_path):
    path = os.path.join(os.path.dirname(starts_path), "attractors.json")
    with open(path) as f:
        transients = json.load(f)["transients"]
    if transients["lifetime"] is None:
        sys.exit(f"{path}: no transient lifetime (fewer than 10 transients end beyond the median)")
    return transients


def read_starts(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    settle = np.array([int(r["settle_period"]) for r in rows])
    force = np.array([float(r["F_m_run"]) for r in rows])
    if np.any(settle < 0):
        sys.exit(f"{path}: some starts did not settle (settle_period -1); raise run.periods")
    return settle, force


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    out = argv[1]
    attractor_fm = None
    series = []
    args = argv[2:]
    while args:
        arg = args.pop(0)
        if arg == "--fm":
            attractor_fm = float(args.pop(0))
            continue
        if not args:
            sys.exit(f"{arg}: a label needs its starts.csv")
        path = args.pop(0)
        series.append((arg, *read_starts(path), read_transients(path)))
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 4.8))
    for label, settle, _, transients in series:
        n = np.sort(settle)
        survival = 1.0 - np.arange(1, len(n) + 1) / len(n)
        onset, tau = transients["from_period"], transients["lifetime"]
        error = transients["lifetime_error"]
        beyond = np.count_nonzero(settle > onset) / len(settle)
        print(f"{label}: {len(settle)} starts, median {onset:.0f}, beyond it tau = {tau:.1f} "
              f"+- {error:.1f} periods, constant rate: {transients['constant_rate']}")
        line, = left.step(n, survival, where="post", label=f"{label} (tau = {tau:.0f} +- {error:.0f})")
        fit = np.linspace(onset, n.max(), 50)
        left.plot(fit, beyond * np.exp(-(fit - onset) / tau), ls="--", color=line.get_color(), lw=1)
    left.set_yscale("log")
    left.set_ylim(0.5 / max(len(s[1]) for s in series), 1.05)
    left.set_xlabel("period n where the transient ended (cycle entry)")
    left.set_ylabel("share of starts still in the transient after n periods")
    left.grid(True, which="both", alpha=0.3)
    left.legend(fontsize=9)
    label, settle, force, _ = series[0]
    right.scatter(settle, force, s=8, alpha=0.6, label=f"{label}: one start each")
    if attractor_fm is not None:
        right.axhline(attractor_fm, color="k", ls="--", lw=1,
                      label=f"the attractor's F_m = {attractor_fm:g}")
    right.set_xscale("log")
    right.set_xlabel("period n where the transient ended")
    right.set_ylabel("F_m of the start's run (recorded window)")
    right.grid(True, which="both", alpha=0.3)
    right.legend(fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main(sys.argv)
