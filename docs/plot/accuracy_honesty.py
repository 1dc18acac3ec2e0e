"""Is run.accuracy_mode = "auto" honest? F_m in auto mode against strict mode, both at tolerance
1e-6, on the non-periodic points of paper-scale study samples (docs/performance.md).

    build/bin/gapchain-sweep data/studies/paper-scale.json --subset 2000 --seed 1 --out /tmp/ps1.csv
    build/bin/gapchain-sweep data/studies/paper-scale.json --subset 2000 --seed 2 --out /tmp/ps2.csv
    PYTHONPATH=build/python python3 docs/plot/accuracy_honesty.py /tmp/ps1.csv /tmp/ps2.csv \\
        --points 300 --out docs/data/accuracy-honesty.csv --png docs/img/accuracy-honesty.png

A second, independent sample (seeds 3 and 4) is docs/data/accuracy-honesty-2.csv; the pooled
summary and histogram of per-point CSVs already computed, with no run:

    python3 docs/plot/accuracy_honesty.py --summarise docs/data/accuracy-honesty.csv \
        docs/data/accuracy-honesty-2.csv --png docs/img/accuracy-honesty.png

Non-periodic: the sample's rows whose run never settled (status "completed"). --points of them
are drawn (seeded) and run twice through the Python module: auto mode with every default (its
F_m_error as a user gets it), and strict mode without the twin check (which changes no F_m).
Prints the mean relative difference (auto - strict) / strict with its standard error, and the
share of points where |auto - strict| exceeds auto's F_m_error; writes the per-point CSV and a
histogram of the relative differences.
"""
import argparse
import csv
import math
import random
import sys
import time
from multiprocessing import Pool

KEYS = ("Nm", "fc", "eps", "e_r", "f_r")


def run_point(row):
    import gapchain

    p = {"Nm": int(row["Nm"]), **{k: float(row[k]) for k in KEYS[1:]}}
    t0 = time.monotonic()
    auto = gapchain.simulate(**p, periods=1000, tolerance=1e-6)
    t1 = time.monotonic()
    strict = gapchain.simulate(**p, periods=1000, tolerance=1e-6, accuracy_mode="strict",
                               multistability_check=False)
    t2 = time.monotonic()
    # The control: strict at the study's tolerance 1e-4, another trajectory of the same row
    # with no relaxation at all.
    control = gapchain.simulate(**p, periods=1000, tolerance=1e-4, accuracy_mode="strict",
                                multistability_check=False)
    return {**p, "F_m_auto": auto["F_m"], "F_m_error_auto": auto["F_m_error"],
            "mode_used": auto["accuracy_mode_used"], "multistable_auto": int(auto["multistable"]),
            "F_m_strict": strict["F_m"], "F_m_error_strict": strict["F_m_error"],
            "settled_strict": int(strict["steady_state_period"] is not None),
            "F_m_strict_1e-4": control["F_m"],
            "seconds_auto": t1 - t0, "seconds_strict": t2 - t1}


def mean_and_error(d):
    n = len(d)
    mean = sum(d) / n
    sd = math.sqrt(sum((x - mean) ** 2 for x in d) / (n - 1))
    return mean, sd / math.sqrt(n), sd


def sign_test(d):
    """Two-sided sign test p-value of the nonzero differences (normal approximation)."""
    pos = sum(x > 0 for x in d)
    neg = sum(x < 0 for x in d)
    n = pos + neg
    z = (abs(pos - neg) - 1) / math.sqrt(n) if n else 0.0
    return pos, neg, math.erfc(max(z, 0.0) / math.sqrt(2.0))


def summary(rows):
    used = [r for r in rows if r["F_m_strict"] > 0]
    d = [(r["F_m_auto"] - r["F_m_strict"]) / r["F_m_strict"] for r in used]
    n = len(d)
    mean, se, sd = mean_and_error(d)
    beyond = sum(abs(r["F_m_auto"] - r["F_m_strict"]) > r["F_m_error_auto"] for r in used)
    both = sum(abs(r["F_m_auto"] - r["F_m_strict"]) >
               math.hypot(r["F_m_error_auto"], r["F_m_error_strict"]) for r in used)
    relaxed = [r for r in used if r["mode_used"] == "relaxed"]
    dr = [(r["F_m_auto"] - r["F_m_strict"]) / r["F_m_strict"] for r in relaxed]
    mr = sum(dr) / len(dr) if dr else float("nan")
    ser = (math.sqrt(sum((x - mr) ** 2 for x in dr) / (len(dr) - 1)) / math.sqrt(len(dr))
           if len(dr) > 1 else float("nan"))
    ta = sum(r["seconds_auto"] for r in rows)
    ts = sum(r["seconds_strict"] for r in rows)
    print(f"points {n} (relaxed {len(relaxed)}, auto multistable "
          f"{int(sum(r['multistable_auto'] for r in used))}, strict settled "
          f"{int(sum(r['settled_strict'] for r in used))})")
    print(f"mean relative difference (auto - strict) / strict: {mean:+.4f} +- {se:.4f} "
          f"(standard error; t = {mean / se:+.2f}, two-sided p = "
          f"{math.erfc(abs(mean / se) / math.sqrt(2.0)):.3f}); sd {sd:.4f}")
    print(f"relaxed points only: {mr:+.4f} +- {ser:.4f} (t = {mr / ser:+.2f})")
    pos, neg, p = sign_test(d)
    d_sorted = sorted(d)
    print(f"median {d_sorted[n // 2]:+.4f}; sign test: {pos} above, {neg} below, p = {p:.3f}")
    trimmed = d_sorted[n // 100: n - n // 100]
    tm, tse, _ = mean_and_error(trimmed)
    print(f"mean without the largest 1 % each side: {tm:+.4f} +- {tse:.4f} (t = {tm / tse:+.2f})")
    c = [(r["F_m_strict_1e-4"] - r["F_m_strict"]) / r["F_m_strict"] for r in used]
    cm, cse, csd = mean_and_error(c)
    cb = sum(abs(r["F_m_strict_1e-4"] - r["F_m_strict"]) > r["F_m_error_strict"] for r in used)
    print(f"control, strict 1e-4 against strict 1e-6: {cm:+.4f} +- {cse:.4f} (t = {cm / cse:+.2f});"
          f" sd {csd:.4f}; beyond strict 1e-6's F_m_error: {cb} ({100.0 * cb / n:.1f} %)")
    print(f"|auto - strict| > auto's F_m_error: {beyond} of {n} ({100.0 * beyond / n:.1f} %); "
          f"> both errors combined: {both} ({100.0 * both / n:.1f} %)")
    print(f"core seconds: auto {ta:.1f}, strict without twin {ts:.1f} (ratio {ts / ta:.2f})")
    return d


def plot(d, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4))
    bins = [0.5 * k - 10.25 for k in range(42)]
    ax.hist([min(max(100.0 * x, -10.0), 10.0) for x in d], bins=bins, color="#4477aa",
            edgecolor="white")
    mean = 100.0 * sum(d) / len(d)
    ax.axvline(0.0, color="black", lw=1)
    ax.axvline(mean, color="#cc3311", lw=1.5, ls="--", label=f"mean {mean:+.2f} %")
    ax.set_xlabel("(F_m auto - F_m strict) / F_m strict  [%], tolerance 1e-6 (clipped to +-10)")
    ax.set_ylabel("points")
    ax.set_title(f"{len(d)} non-periodic points of the paper-scale grid")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def read_points(paths):
    """Per-point rows of CSVs this script wrote, numbers as numbers."""
    rows = []
    for path in paths:
        with open(path) as f:
            for r in csv.DictReader(f):
                rows.append({k: (v if k == "mode_used" else float(v)) for k, v in r.items()})
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("samples", nargs="+", help="gapchain-sweep CSVs of paper-scale subsets "
                    "(with --summarise: per-point CSVs this script wrote)")
    ap.add_argument("--summarise", action="store_true",
                    help="pool per-point CSVs already written: summary and histogram, no run")
    ap.add_argument("--points", type=int, default=300)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--processes", type=int, default=2)
    ap.add_argument("--out")
    ap.add_argument("--png")
    a = ap.parse_args()
    if a.summarise:
        d = summary(read_points(a.samples))
        if a.png:
            plot(d, a.png)
        return
    if not a.out:
        sys.exit("--out is required unless --summarise")
    rows = []
    for path in a.samples:
        with open(path) as f:
            rows += [r for r in csv.DictReader(f) if r["status"] == "completed"]
    if len(rows) < a.points:
        sys.exit(f"only {len(rows)} non-periodic rows in the samples, fewer than --points")
    random.Random(a.seed).shuffle(rows)
    chosen = rows[: a.points]
    with Pool(a.processes) as pool:
        results = []
        for i, r in enumerate(pool.imap(run_point, chosen, chunksize=1)):
            results.append(r)
            if sys.stderr.isatty():
                print(f"\r{i + 1}/{len(chosen)}", end="", file=sys.stderr)
    tmp = a.out + ".part"
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(results[0].keys()))
        w.writeheader()
        w.writerows(results)
    import os
    os.replace(tmp, a.out)
    d = summary(results)
    if a.png:
        plot(d, a.png)


if __name__ == "__main__":
    main()
