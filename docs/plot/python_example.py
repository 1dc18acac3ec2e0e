#!/usr/bin/env python3
"""docs/python.md's figures, made with the Python module gapchain and matplotlib.
Usage (from the repository root, after the build):
    PYTHONPATH=build/python python3 docs/plot/python_example.py fig13|map|modes [OUT.png]
Writes docs/img/python-<figure>.png unless OUT.png is given, and prints what it computed."""
import sys

import gapchain  # first: it makes Debian's NumPy importable for a pyenv python3 too
import numpy as np

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def fig13(out):
    """Fig 13's line: section points of u1 and F_m over f_r."""
    d = gapchain.bifurcation(Nm=5, fc=60, eps=0.5, e_r=0.06, param="f_r", from_=2.0, to=4.5,
                             steps=250, transient=200, record=100)
    s = d["section"]
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
    top.plot(s["value"], s["point"], ",k")
    top.set_ylabel("u1 at phase 0 (stroboscopic)")
    top.set_title("Nm=5 fc=60 eps=0.5 e_r=0.06: gapchain.bifurcation")
    periodic = d["period"] > 0
    bottom.plot(d["value"][periodic], d["F_m"][periodic], ".", ms=3, label="periodic")
    bottom.plot(d["value"][~periodic], d["F_m"][~periodic], ".", ms=3, label="not periodic")
    bottom.set_xlabel("f_r")
    bottom.set_ylabel("F_m")
    bottom.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    i = int(np.argmax(d["F_m"]))
    print(f"{len(d['value'])} values, {periodic.sum()} periodic, max F_m {d['F_m'][i]:.4f} at "
          f"f_r = {d['value'][i]:.3f}, {d['wall_time_s']:.1f} s on {d['threads_used']} threads")


def regime_map(out):
    """A regime map over (e_r, f_r) for Nm = 3, fc = 100 (as docs/chaos.md's Fig 2 map)."""
    e_r = np.linspace(0.0, 1.5, 50)
    f_r = np.linspace(0.1, 5.0, 50)
    m = gapchain.regime_map(Nm=3, fc=100, eps=0.5, e_r=e_r, f_r=f_r)
    names = ["no-contact", "periodic", "quasi-periodic", "chaotic"]
    colors = matplotlib.colors.ListedColormap(["#dddddd", "#4c72b0", "#dd8452", "#c44e52"])
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))
    extent = [f_r[0], f_r[-1], e_r[0], e_r[-1]]
    image = left.imshow(m["code"], origin="lower", aspect="auto", extent=extent, cmap=colors,
                        vmin=-0.5, vmax=3.5, interpolation="nearest")
    bar = fig.colorbar(image, ax=left, ticks=range(4))
    bar.ax.set_yticklabels(names)
    left.set_title("regime (Nm=3 fc=100 eps=0.5)")
    force = right.imshow(m["F_m"], origin="lower", aspect="auto", extent=extent,
                         interpolation="nearest")
    fig.colorbar(force, ax=right, label="F_m")
    right.set_title("F_m")
    for ax in (left, right):
        ax.set_xlabel("f_r")
        ax.set_ylabel("e_r")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    counts = {n: int((m["code"] == k).sum()) for k, n in enumerate(names)}
    print(f"{m['code'].size} cells: {counts}, {m['wall_time_s']:.1f} s on {m['threads_used']} "
          f"threads")


def modes(out):
    """Exact linear-chain frequencies against eq (26), and eq (26)'s relative error."""
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for Nm, fc in [(20, 10), (20, 100), (20, 1000)]:
        m = gapchain.modes(Nm, fc)
        line, = left.plot(m["mode"], m["frequency"], "o", ms=4, label=f"exact, fc={fc}")
        left.plot(m["mode"], m["approx"], "-", color=line.get_color(), label=f"eq (26), fc={fc}")
        right.plot(m["mode"], 100 * m["rel_error"], "o-", ms=3, label=f"fc={fc}")
        worst = int(np.argmax(np.abs(m["rel_error"])))
        print(f"Nm={Nm} fc={fc}: f_1 = {m['frequency'][0]:.6f} (eq 26: {m['approx'][0]:.6f}), "
              f"largest |error| {100 * abs(m['rel_error'][worst]):.2f} % at k = "
              f"{m['mode'][worst]}")
    left.set_yscale("log")
    left.set_xlabel("mode k")
    left.set_ylabel("f_k / f0")
    left.set_title("Nm=20: natural frequencies")
    left.legend(fontsize=8)
    right.axhline(0, color="grey", lw=0.5)
    right.set_xlabel("mode k")
    right.set_ylabel("(f_ka - f_k) / f_k  [%]")
    right.set_title("eq (26)'s error")
    right.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    figures = {"fig13": fig13, "map": regime_map, "modes": modes}
    if len(sys.argv) not in (2, 3) or sys.argv[1] not in figures:
        sys.exit(__doc__)
    figures[sys.argv[1]](sys.argv[2] if len(sys.argv) == 3 else
                         f"docs/img/python-{sys.argv[1]}.png")
