#!/usr/bin/env python3
"""Hertz against linear contact at equal peak stiffness, for the Table 4 row in reduced units.

For each forcing frequency: run the linear law (contact stiffness k: fc at the walls, fc/2
between bodies); then give every contact the Hertz law with coefficient c k, and choose c so
that the Hertz contact's tangent stiffness at its own peak penetration p equals k:
1.5 c sqrt(p) = 1. p depends on c, so c is found by fixed-point iteration (the residual is
printed). Both laws share the force scale sqrt(fc), so their F_m compare directly.
Writes a CSV to stdout-named file and prints a Markdown table.
Usage: python3 docs/plot/hertz_vs_linear.py BUILD_BIN_DIR OUT.csv"""
import json
import math
import subprocess
import sys
import tempfile

bin_dir, out_csv = sys.argv[1], sys.argv[2]
row = {"Nm": 46, "fc": 559, "eps": 0.1, "e_r": 0.22}
f_values = [0.6, 1.0, 1.4]
iterations = 4


def simulate(f_r, law, factor=1.0):
    sets = [f"model.{k}={v}" for k, v in row.items()] + [f"excitation.f_r={f_r}"]
    if law == "hertz":
        sets += ["model.contact_law=hertz",
                 "model.contact=" + json.dumps([factor] * (row["Nm"] + 1))]
    with tempfile.NamedTemporaryFile(suffix=".json") as scene, \
            tempfile.NamedTemporaryFile(suffix=".json") as out:
        scene.write(b"{}")
        scene.flush()
        cmd = [f"{bin_dir}/gapchain-sim", scene.name, "--quiet", "--out", out.name]
        for s in sets:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True)
        return json.load(open(out.name))


def penetration(result, factor):
    """Peak penetration from F_m = factor k_j p^phi / sqrt(fc) at the contact j of F_m."""
    j = result["F_m_contact"]
    k = row["fc"] if j in (0, row["Nm"]) else row["fc"] / 2
    return result["F_m"] * math.sqrt(row["fc"]) / (factor * k)


lines = ["f_r,F_m_linear,F_m_linear_error,p_linear,hertz_factor,F_m_hertz,F_m_hertz_error,"
         "p_hertz,stiffness_residual"]
print("| f_r | linear F_m | its peak penetration | Hertz factor c | Hertz F_m | its peak "
      "penetration | 1.5 c sqrt(p) - 1 |")
print("| --- | --- | --- | --- | --- | --- | --- |")
for f_r in f_values:
    lin = simulate(f_r, "linear")
    p_lin = penetration(lin, 1.0)
    factor = 1.0 / (1.5 * math.sqrt(p_lin))
    for _ in range(iterations):
        hz = simulate(f_r, "hertz", factor)
        p_hz = penetration(hz, factor) ** (2.0 / 3.0)
        factor = 1.0 / (1.5 * math.sqrt(p_hz))
    hz = simulate(f_r, "hertz", factor)
    p_hz = penetration(hz, factor) ** (2.0 / 3.0)
    residual = 1.5 * factor * math.sqrt(p_hz) - 1.0
    lines.append(f"{f_r},{lin['F_m']},{lin['F_m_error']},{p_lin},{factor},{hz['F_m']},"
                 f"{hz['F_m_error']},{p_hz},{residual}")
    print(f"| {f_r} | {lin['F_m']:.3f} +- {lin['F_m_error']:.2g} | {p_lin:.4g} | {factor:.4g} | "
          f"{hz['F_m']:.3f} +- {hz['F_m_error']:.2g} | {p_hz:.4g} | {residual:+.1e} |")
with open(out_csv, "w") as f:
    f.write("\n".join(lines) + "\n")
