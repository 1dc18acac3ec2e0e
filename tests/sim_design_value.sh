#!/usr/bin/env bash
# gapchain-sim --attractors: the design value over the row's attractors, and its bad inputs
# (exit 2, one line naming the flag or key, no output file). Usage: sim_design_value.sh SIM SCENES
set -u
sim=$1
scenes=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
# Fig 13's line at f_r = 3.2: from rest the row reaches the weaker attractor; the torus (F_m
# 0.385) is the design value (docs/attractors.md).
"$sim" "$scenes/fig13.json" --set excitation.f_r=3.2 --set run.periods=600 \
    --set run.transient_periods=300 --attractors 60 --threads 2 --out "$dir/f13.json" >"$dir/stdout" 2>&1
rc=$?
if [ "$rc" -ne 0 ]; then echo "FAIL fig13: exit $rc"; cat "$dir/stdout"; fail=1; fi
grep -q "multistable: this run's start reached a weaker attractor" "$dir/stdout" ||
    { echo "FAIL fig13: no multistable line"; cat "$dir/stdout"; fail=1; }
python3 - "$dir/f13.json" <<'PY' || fail=1
import json, sys
d = json.load(open(sys.argv[1]))
v = d["design_value"]
ok = d["multistable"] and v["start_below"] and not v["run_above"] and v["attractors"] >= 2 \
    and abs(v["F_m_max"] - 0.3853) < 2e-3 and v["F_m_max"] > d["F_m"] and v["samples"] == 60 \
    and v["center"] == [0.0] * 10
if not ok:
    print("FAIL fig13 JSON:", v, d["F_m"], d["multistable"])
sys.exit(0 if ok else 1)
PY
# A physical scene's design value also in newtons, at the run's own conversion.
"$sim" "$scenes/table4-experiment-harmonic.json" --set run.periods=100 --attractors 2 \
    --out "$dir/phys.json" >/dev/null 2>&1 || { echo "FAIL physical: exit $?"; fail=1; }
python3 - "$dir/phys.json" <<'PY' || fail=1
import json, sys
d = json.load(open(sys.argv[1]))
v = d["design_value"]
ok = abs(v["F_m_max_newton"] / v["F_m_max"] - d["F_m_newton"] / d["F_m"]) < 1e-9 * d["F_m_newton"] / d["F_m"]
if not ok:
    print("FAIL physical JSON:", v)
sys.exit(0 if ok else 1)
PY
# A start overlapping a contact takes F_m at t = 0, above the one attractor's 0.39, and settles:
# its bar covers the orbit (maximum_in_transient), and the design line says where F_m was taken.
"$sim" "$scenes/fig13.json" --set run.transient_periods=0 --set 'initial.u=[0.5,0,0,0,0]' \
    --attractors 10 --out "$dir/overlap.json" >"$dir/stdout" 2>&1
grep -q "taken in its transient before the orbit (the largest attractor's: F_m = 0.3909" \
    "$dir/stdout" ||
    { echo "FAIL overlap: no transient design line"; cat "$dir/stdout"; fail=1; }
# Without --attractors, a run that does not settle says that nothing else was looked for.
"$sim" "$scenes/fig13.json" --set excitation.f_r=3.2 --set run.periods=600 \
    --set run.transient_periods=300 >"$dir/stdout" 2>&1
grep -q "other attractors were not looked for" "$dir/stdout" ||
    { echo "FAIL hint: missing"; cat "$dir/stdout"; fail=1; }

echo '{"model": {"Nm": 2, "fc": 10, "e_r": 0.5, "mass": [1, 2]}, "run": {"periods": 50}}' >"$dir/uneven.json"
bad() { # name, expected fragment, args...
    local name=$1 key=$2; shift 2
    "$sim" "$@" --out "$dir/out_$name" >"$dir/stdout" 2>"$dir/stderr"
    local rc=$? lines
    lines=$(wc -l <"$dir/stderr")
    if [ "$rc" -ne 2 ]; then echo "FAIL $name: exit $rc, expected 2"; fail=1; fi
    if [ "$lines" -ne 1 ]; then echo "FAIL $name: $lines stderr lines"; cat "$dir/stderr"; fail=1; fi
    grep -q -- "$key" "$dir/stderr" || { echo "FAIL $name: lacks '$key'"; cat "$dir/stderr"; fail=1; }
    if [ -e "$dir/out_$name" ]; then echo "FAIL $name: output left behind"; fail=1; fi
}
bad seed_alone "--seed" "$scenes/fig5.json" --seed 3
bad box_alone "--box" "$scenes/fig5.json" --attractors 0 --box 2
bad negative "--attractors" "$scenes/fig5.json" --attractors -1
bad box_range "--box" "$scenes/fig5.json" --attractors 5 --box 0
bad uneven "gapchain-sim --attractors" "$dir/uneven.json" --attractors 5
bad short_window "run.periods" "$scenes/fig5.json" --attractors 5 --set run.periods=10
[ "$fail" -eq 0 ] && echo "all design-value checks passed"
exit $fail
