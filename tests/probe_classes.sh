#!/usr/bin/env bash
# The 23 defect classes of the reliability probe (../shared/reports/reliability-probe-2026-11-22.md),
# each reproduced as the report gives it and checked against what the README promises, a
# 24th and 25th from the probes of 2026-11-24, a 26th from a later one that day, a 27th
# from that of 2026-11-26, and a 28th from that of 2026-11-27.
# Usage: probe_classes.sh BIN_DIR SOURCE_DIR   (prints "class N: ok" or "class N: FAIL ...")
set -u
bin=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
scenes="$src/data/scenes"
dir=$(mktemp -d)
trap 'umount "$dir/full" 2>/dev/null; rm -rf "$dir"' EXIT
cd "$dir" || exit 1
failed=()

# expect CLASS RC PATTERN CMD...: exit status RC, and the last stderr line matches PATTERN.
expect() {
    local class=$1 rc=$2 pattern=$3
    shift 3
    timeout -s KILL 60 "$@" >"$dir/stdout" 2>"$dir/stderr"
    local got=$?
    local last
    last=$(grep -v '^gapchain-[a-z]*: [0-9]* points in the study' "$dir/stderr" | tail -n 1)
    if [ "$got" -ne "$rc" ] || ! grep -qE -- "$pattern" <<<"$last"; then
        echo "class $class: FAIL: $* -> exit $got (expected $rc): $last"
        failed+=("$class")
        return 1
    fi
    return 0
}
# one_line CLASS: the last command wrote exactly one line on stderr.
one_line() {
    if [ "$(wc -l <"$dir/stderr")" -ne 1 ]; then
        echo "class $1: FAIL: $(wc -l <"$dir/stderr") stderr lines, expected one"
        failed+=("$1")
    fi
}
# absent CLASS PATH...: none of the paths exists.
absent() {
    local class=$1
    shift
    for p in "$@"; do
        if [ -e "$p" ]; then
            echo "class $class: FAIL: $p was left behind"
            failed+=("$class")
        fi
    done
}
verdict() { # CLASS
    if printf '%s\n' "${failed[@]:-}" | grep -qx "$1"; then return; fi
    echo "class $1: ok"
}

small_study() { # PATH [periods]
    cat >"$1" <<EOF
{"scene": {"model": {"Nm": 3, "eps": 0.5, "fc": 60}, "excitation": {"f_r": 1.0},
           "run": {"periods": ${2:-200}, "scheme": "rk4", "steady_state": false,
                   "estimate_error": false}},
 "parameters": {"e_r": {"lin": [0, 0.3, 20]}, "f_r": {"lin": [2, 4.5, 10]}},
 "sample": "grid", "keep": ["F_m", "per_body", "steady_state_period"]}
EOF
}
small_study study.json
cp "$scenes/fig5.json" fig5.json
seismic="$scenes/table4-experiment-seismic.json"

# 1. Disk full in the middle of a sweep: exit 1 naming the file and the OS reason, no abort.
mkdir full
if mount -t tmpfs -o size=64k tmpfs full 2>/dev/null; then
    dd if=/dev/zero of=full/fill bs=1k count=52 2>/dev/null
    expect 1 1 "full/r.csv.*(No space left|disk full)" "$bin/gapchain-sweep" study.json --threads 2 --out full/r.csv
    umount full
else
    echo "class 1: skipped the tmpfs part (mount not permitted here)"
fi
verdict 1

# 2. Resuming into a CSV started by another study is refused.
"$bin/gapchain-sweep" study.json --out two.csv >/dev/null 2>&1
head -n 101 two.csv >two.tmp && mv two.tmp two.csv
small_study other.json 150
expect 2 2 "two.csv: was started by another study" "$bin/gapchain-sweep" other.json --out two.csv
[ "$(wc -l <two.csv)" -eq 101 ] || { echo "class 2: FAIL: the CSV was changed"; failed+=(2); }
verdict 2

# 3. Tools that need a forcing period refuse record and Kanai-Tajimi scenes.
expect 3 2 "needs harmonic forcing" "$bin/gapchain-classify" "$seismic" --out c.json
expect 3 2 "harmonic|uniform row" "$bin/gapchain-classify" "$seismic" --map --e_r 0:1:2 --f_r 1:2:2 --out cmap
expect 3 2 "harmonic|uniform row" "$bin/gapchain-bifurcation" "$seismic" --steps 2 --out bif
expect 3 2 "harmonic|uniform row" "$bin/gapchain-bounds" "$seismic"
{ printf '{"scene": '; cat "$seismic"; printf ', "parameters": {"excitation.seed": [1, 2]}, "keep": ["F_m", "regime"]}\n'; } >seismic-study.json
expect 3 2 "regime" "$bin/gapchain-sweep" seismic-study.json --out seismic.csv
absent 3 c.json cmap bif seismic.csv
verdict 3

# 4. Duplicate JSON keys are refused, naming the key, at every level.
echo '{"model":{"Nm":5,"fc":60,"e_r":0.06},"run":{"periods":20},"model":{"Nm":7}}' >dup1.json
echo '{"model":{"Nm":5,"fc":60,"fc":100},"run":{"periods":20}}' >dup2.json
expect 4 2 "^gapchain-sim: dup1.json: model: duplicate key" "$bin/gapchain-sim" dup1.json --out d.json
expect 4 2 "model.fc: duplicate key" "$bin/gapchain-sim" dup2.json --out d.json
verdict 4

# 5. modes: --Nm 0 and --fc 0 are refused, not replaced by defaults.
expect 5 2 "--Nm" "$bin/gapchain-modes" --Nm 0 --out m.json
expect 5 2 "--fc" "$bin/gapchain-modes" --Nm 3 --fc 0 --out m.json
absent 5 m.json
verdict 5

# 6. Work that would take hours is refused at once, with the estimate and the key to raise (the
#    inner timeout guards against a hang: refusing takes seconds, a Kanai-Tajimi record of 1e5 s
#    is built first; the work would take hours).
expect 6 2 "run.max_work|excitation.f_r" timeout 60 "$bin/gapchain-sim" fig5.json --set excitation.f_r=1e-6 --out h.json
expect 6 2 "run.max_work|run.step" timeout 60 "$bin/gapchain-sim" fig5.json --set run.step=1e-9 --out h.json
expect 6 2 "run.max_work" timeout 60 "$bin/gapchain-sim" "$seismic" --set excitation.duration=1e5 --out h.json
expect 6 2 "--max-dense" timeout 60 "$bin/gapchain-modes" --Nm 20000 --out h.json
expect 6 0 "" timeout 60 "$bin/gapchain-sim" fig5.json --set run.periods=20 --set run.max_work=1e9 --out h.json
verdict 6

# 7. An output path equal to an input or to another output is refused; the input is kept.
cp fig5.json copy.json
expect 7 2 "--out: .*input" "$bin/gapchain-sim" copy.json --out copy.json
expect 7 2 "--trajectory: .*input" "$bin/gapchain-sim" copy.json --trajectory copy.json --out o.json
expect 7 2 "--trajectory: .*--out" "$bin/gapchain-sim" copy.json --out x.csv --trajectory x.csv
cmp -s copy.json fig5.json || { echo "class 7: FAIL: the scene was overwritten"; failed+=(7); }
verdict 7

# 8. A study giving one parameter twice is refused.
cat >twice.json <<'EOF'
{"scene": {"model": {"Nm": 2}, "run": {"periods": 5}},
 "parameters": {"e_r": [0.1, 0.2], "model.e_r": [0.3]}, "sample": "grid", "keep": ["F_m"]}
EOF
expect 8 2 "given twice" "$bin/gapchain-sweep" twice.json --out tw.csv
absent 8 tw.csv tw.csv.json
verdict 8

# 9. Output paths are checked before computing (a long run fails at once). The runs asked for
#    take minutes (sim 2e6 periods ~150 s, lyapunov far more) and the refusals well under a
#    second, so a 30 s guard tells them apart on a loaded machine too. (classify runs its own
#    fixed 400 periods, whatever run.periods says: its check is the message only.)
start=$(date +%s)
expect 9 2 "--out: /proc/x" "$bin/gapchain-sim" fig5.json --set run.periods=2000000 --set run.steady_state=false --out /proc/x
expect 9 2 "--out: /proc/x" "$bin/gapchain-lyapunov" fig5.json --set run.periods=2000000 --out /proc/x/l.json
expect 9 2 "--out: /proc/x" "$bin/gapchain-classify" fig5.json --out /proc/x
[ $(($(date +%s) - start)) -le 30 ] || { echo "class 9: FAIL: took more than 30 s"; failed+=(9); }
verdict 9

# 10. SIGINT during a run removes the temporary trajectory file.
"$bin/gapchain-sim" fig5.json --set run.periods=400000 --set run.steady_state=false --set output.trajectory_every=100 \
    --trajectory t.csv --out t.json >/dev/null 2>&1 &
pid=$!
sleep 1
kill -INT "$pid"
for _ in $(seq 1 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
kill -KILL "$pid" 2>/dev/null
wait "$pid"
rc=$?
[ "$rc" -eq 130 ] || { echo "class 10: FAIL: exit $rc after SIGINT, expected 130"; failed+=(10); }
absent 10 t.csv t.json
ls | grep -q '\.tmp' && { echo "class 10: FAIL: temporary left: $(ls | grep '\.tmp')"; failed+=(10); }
verdict 10

# 11. Bad sweep input is found before any file is created.
expect 11 2 "--threads" "$bin/gapchain-sweep" study.json --threads -1 --out b11.csv
expect 11 2 "--threads" "$bin/gapchain-sweep" study.json --threads 100000 --out b11.csv
cat >hertz-regime.json <<'EOF'
{"scene": {"model": {"Nm": 2, "contact_law": "hertz"}, "run": {"periods": 5}},
 "parameters": {"e_r": [0.1, 0.2]}, "keep": ["F_m", "regime"]}
EOF
expect 11 2 "regime" "$bin/gapchain-sweep" hertz-regime.json --out b11.csv
# Each axis is affordable alone; their corner (Nm 1976 at f_r 0.01) is above run.max_work.
cat >big-corner.json <<'EOF'
{"scene": {"model": {"Nm": 1, "fc": 100, "eps": 0.1, "e_r": 0.5}, "run": {"periods": 1000}},
 "parameters": {"Nm": {"lin": [1, 1976, 80]}, "f_r": {"lin": [1, 0.01, 80]}}}
EOF
expect 11 2 "run.max_work.*Nm = 1976, f_r = 0.01" "$bin/gapchain-sweep" big-corner.json --out b11.csv
absent 11 b11.csv b11.csv.json
verdict 11

# 12. A plot that gnuplot fails to write is a failure (exit 1), never "wrote ...".
mkdir -p fakebin
printf '#!/bin/sh\ncat >/dev/null\nexit 1\n' >fakebin/gnuplot
chmod +x fakebin/gnuplot
expect 12 1 "gnuplot" env PATH="$dir/fakebin:$PATH" "$bin/gapchain-classify" fig5.json --map --e_r 0.4:0.6:2 --f_r 1:1.2:2 --transient 10 --record 20 --out map12
printf '#!/bin/sh\ncat >/dev/null\n: > "$(ls -t /proc/$$/cwd/*.png 2>/dev/null | head -1)" 2>/dev/null\nexit 0\n' >fakebin/gnuplot
expect 12 1 "gnuplot|PNG|png" env PATH="$dir/fakebin:$PATH" "$bin/gapchain-lyapunov" fig5.json --set run.periods=20 --out ly12.json
verdict 12

# 13. A folder tool that fails leaves no folder behind.
expect 13 2 "harmonic" "$bin/gapchain-poincare" "$seismic" --out pc13
expect 13 2 "harmonic" "$bin/gapchain-spectrum" "$seismic" --out sp13
absent 13 pc13 sp13
verdict 13

# 14. Sizes that would exhaust memory are refused with the limit and the key, no bad_alloc.
expect 14 2 "--max-dense|--modes" "$bin/gapchain-modes" --Nm 1000000 --modes 1000000 --out m14.json
expect 14 2 "--max-dense" "$bin/gapchain-modes" --method dense --Nm 200000 --out m14.json
echo '{"units": "physical", "excitation": {"type": "kanai_tajimi", "sample_interval": 1e-9}}' >kt14.json
expect 14 2 "excitation.sample_interval" "$bin/gapchain-sim" kt14.json --out m14.json
grep -q "bad_alloc\|vector::" "$dir/stderr" && { echo "class 14: FAIL: raw exception text"; failed+=(14); }
verdict 14

# 15. An unusable output folder is exit 2 with the reason, for file and folder tools alike.
touch existing
expect 15 2 "--out: /proc/y" "$bin/gapchain-bifurcation" --steps 2 --out /proc/y
expect 15 2 "--out: existing" "$bin/gapchain-bifurcation" --steps 2 --out existing
expect 15 2 "--out: /proc/y" "$bin/gapchain-sim" fig5.json --out /proc/y/r.json
verdict 15

# 16. Messages name the key the user wrote.
echo '{"model": {"Nm": 3, "mass": [1e-300, 1, 1]}}' >m16.json
echo '{"units": "physical", "model": {"e": 0.001}, "excitation": {"a0": 1e-300}}' >a16.json
echo '{"units": "physical", "model": {"M": 1e-300}}' >M16.json
echo '{"units": "physical", "excitation": {"type": "kanai_tajimi", "duration": 1e-300}}' >kt16.json
expect 16 2 "^gapchain-sim: model.mass" "$bin/gapchain-sim" m16.json --out o16.json
expect 16 2 "^gapchain-sim: [^:]*excitation.a0" "$bin/gapchain-sim" a16.json --out o16.json
expect 16 2 "^gapchain-sim: [^:]*model.M" "$bin/gapchain-sim" M16.json --out o16.json
expect 16 2 "^gapchain-sim: excitation.duration" "$bin/gapchain-sim" kt16.json --out o16.json
expect 16 2 "^gapchain-sim: excitation.f_r" "$bin/gapchain-sim" fig5.json --set excitation.f_r=1e-12 --out o16.json
expect 16 2 "^gapchain-sim: run.step" "$bin/gapchain-sim" fig5.json --set run.step=1e-300 --out o16.json
verdict 16

# 17. Messages name the flag, not an internal field.
expect 17 2 "^gapchain-spectrum: --segment" "$bin/gapchain-spectrum" fig5.json --segment 1 --out sp17
expect 17 2 "^gapchain-accuracy: --schemes" "$bin/gapchain-accuracy" fig5.json --schemes foo --out ac17
expect 17 2 "^gapchain-modes: --fc" "$bin/gapchain-modes" "$scenes/table4-experiment-harmonic.json" --fc 3 --out m17.json
expect 17 2 "^gapchain-lyapunov: --count" "$bin/gapchain-lyapunov" fig5.json --count 11 --out l17.json
verdict 17

# 18. An unknown study parameter is named as such.
echo '{"scene": {"run": {"periods": 5}}, "parameters": {"foo": [1]}, "keep": ["F_m"]}' >foo.json
expect 18 2 "parameters.foo: unknown" "$bin/gapchain-sweep" foo.json --out f18.csv
verdict 18

# 19. A directory given as the scene says so.
mkdir -p adir
expect 19 2 "adir: is a directory" "$bin/gapchain-sim" adir --out o19.json
expect 19 2 "adir: is a directory" "$bin/gapchain-sweep" adir --out o19.csv
verdict 19

# 20. Malformed shards and seeds are refused.
for shard in 1/2/3 0/1e9 0/4294967297 2/2 -1/2; do
    expect 20 2 "--shard" "$bin/gapchain-sweep" study.json --shard "$shard" --out s20.csv
done
expect 20 2 "--seed" "$bin/gapchain-sweep" study.json --subset 3 --seed -1 --out s20.csv
absent 20 s20.csv
verdict 20

# 21. The message gives the real reason.
expect 21 2 "--trigger: must be a linear signal of the state" "$bin/gapchain-poincare" fig5.json --section event --trigger t --out p21
expect 21 2 "contact_law" "$bin/gapchain-bifurcation" --set model.contact_law=hertz --steps 2 --out b21
expect 21 2 "contact_law" "$bin/gapchain-classify" fig5.json --set model.contact_law=hertz --out c21.json
verdict 21

# 22. Options that do not apply are refused.
expect 22 2 "--e_r requires --map" "$bin/gapchain-classify" fig5.json --e_r 0:1:3 --out c22.json
expect 22 2 "--grid excludes --Nm" "$bin/gapchain-modes" --grid --Nm 7 --out g22
expect 22 2 "--grid excludes --csv" "$bin/gapchain-modes" --grid --csv x.csv --out g22
expect 22 2 "SCENE" "$bin/gapchain-sim" ""
# A flag takes no value: --no-plot=0 turned it off and --no-plot=7 on (session 48's probe).
expect 22 2 "^gapchain-spectrum: --no-plot: a flag takes no value" "$bin/gapchain-spectrum" fig5.json --no-plot=7 --out sp22
one_line 22
absent 22 sp22
expect 22 2 "--follow-doublings: a flag takes no value" "$bin/gapchain-continue" fig5.json --from 1 --to 1.1 --follow-doublings=0 --out c22
absent 22 c22
# An empty value ran as the bare flag: --no-plot= plotted nothing and said nothing.
expect 22 2 "^gapchain-bifurcation: --no-plot: a flag takes no value" "$bin/gapchain-bifurcation" fig5.json --no-plot= --steps 2 --out b22
one_line 22
absent 22 b22
verdict 22

# 23. The small ones.
expect 23 2 "frob" "$bin/gapchain-bench" frob
start=$(date +%s)
expect 23 2 "--threads" "$bin/gapchain-bench" bifurcation --threads -1
[ $(($(date +%s) - start)) -le 2 ] || { echo "class 23: FAIL: --threads checked late"; failed+=(23); }
expect 23 2 "listed twice|twice" "$bin/gapchain-accuracy" fig5.json --schemes rk4 rk4 --out a23
expect 23 2 "--variable" "$bin/gapchain-spectrum" fig5.json --variable t --out sp23
expect 23 0 "" "$bin/gapchain-bounds" fig5.json --out b23.json
grep -q '"eq25_smooth_bound"' b23.json || { echo "class 23: FAIL: bounds --out wrote no JSON"; failed+=(23); }
expect 23 0 "" "$bin/gapchain-bifurcation" --set model.e_r=50 --steps 2 --transient 5 --record 5 --no-plot --out b23
grep -q "max F_m = 0 at" "$dir/stdout" && { echo "class 23: FAIL: no-contact line says max F_m = 0 at"; failed+=(23); }
"$bin/gapchain-sweep" study.json --subset 2 --out s23.csv >/dev/null 2>&1
grep -q "\"study\": \"/" s23.csv.json || { echo "class 23: FAIL: sidecar study path not absolute"; failed+=(23); }
verdict 23

# 24. The probe of 2026-11-24: interrupts reach the orbit tools' warm-up runs and the runs
#     inside gapchain-attractors (one period of a 1e5-body row takes seconds); a malformed
#     --overlay and a continuation that finds no orbit fail cleanly.
# stopped CLASS RC CMD...: started, sent SIGTERM after 1 s, it exits with RC within 20 s.
# (timeout does the signalling: a backgrounded guard subshell, killed, ran this script's EXIT
# trap and removed $dir under every later class.)
stopped() {
    local class=$1 rc=$2
    shift 2
    timeout --preserve-status -s TERM -k 20 1 "$@" >/dev/null 2>&1
    local got=$?
    [ "$got" -eq "$rc" ] || { echo "class $class: FAIL: $* -> exit $got after SIGTERM, expected $rc"; failed+=("$class"); }
}
stopped 24 143 "$bin/gapchain-orbit" "$scenes/fig13.json" --from-transient 3000000 --out o24.json
stopped 24 143 "$bin/gapchain-continue" "$scenes/fig13.json" --from 2.8 --to 3 --transient 3000000 --no-plot --out c24
stopped 24 143 "$bin/gapchain-attractors" "$scenes/fig13.json" --samples 4 --no-plot --set model.Nm=100000 --set run.max_work=1e15 --out a24
absent 24 o24.json c24 a24
printf 'a,b,c\n1,2,3\n' > overlay.csv
expect 24 2 "--overlay" "$bin/gapchain-continue" "$scenes/fig13.json" --from 2.8 --to 3 --overlay overlay.csv --out c24
one_line 24
# Rows cut short, with extra fields or another direction were drawn as they came (session 48).
mkdir -p ov24
printf '{"parameter": "f_r", "base": {"Nm": 5, "fc": 60, "eps": 0.5, "e_r": 0.06, "f_r": 3}}\n' >ov24/bifurcation.json
for row in '2.9,up,0.4' '2.9,up,0.4,0.001,1,100,completed,x' '2.9,sideways,0.4,0.001,1,100,completed' '2.9x,up,0.4,0.001,1,100,completed' '2.9,up,0.4abc,0.001,1,100,completed'; do
    printf 'value,direction,F_m,F_m_error,period,points,status\n%s\n' "$row" >ov24/summary.csv
    expect 24 2 "--overlay: row 2 of .* needs 7 fields as its header, a finite value, a direction up or down" "$bin/gapchain-continue" "$scenes/fig13.json" --from 2.8 --to 3 --overlay ov24/summary.csv --out c24
done
expect 24 1 "no orbit found" "$bin/gapchain-continue" "$scenes/fig13.json" --no-plot --param eps --from 0 --to 0.5 --out c24
absent 24 c24
# The messages name the flag, the real bounds and the real value.
expect 24 2 "--box: must be in 1e-09 to 100" "$bin/gapchain-attractors" "$scenes/fig13.json" --box 0 --out a24
expect 24 2 "--seed: must be an integer" "$bin/gapchain-attractors" "$scenes/fig13.json" --seed 1e5 --out a24
expect 24 2 "--grid: .*got \"\"" "$bin/gapchain-attractors" "$scenes/fig13.json" --grid '' --out a24
expect 24 2 "--grid: .*got \"u1,v1,u2\"" "$bin/gapchain-attractors" "$scenes/fig13.json" --grid u1,v1,u2 --out a24
expect 24 2 "--to: excitation.f_r.*got inf" "$bin/gapchain-attractors" "$scenes/fig13.json" --param f_r --from 3 --to inf --steps 3 --out a24
expect 24 2 "--from: excitation.f_r.*got nan" "$bin/gapchain-bifurcation" --from nan --out b24
expect 24 2 "--phase" "$bin/gapchain-bifurcation" --phase 1 --out b24
absent 24 a24 b24
verdict 24

# 25. The probe of 2026-11-24 (session 26).
nm2='{"model": {"Nm": 2, "fc": 200, "eps": 0.1, "e_r": 0.351}, "excitation": {"f_r": 0.626}}'
echo "$nm2" >nm2.json
# A folder name is never handed to a shell: a quote in it neither fails nor runs a command.
expect 25 0 "" "$bin/gapchain-attractors" nm2.json --samples 2 --grid u1,v1 --resolution 2 --out "x';touch INJECTED;'"
absent 25 INJECTED
[ -s "x';touch INJECTED;'/basins.png" ] || { echo "class 25: FAIL: no basins.png in the quoted folder"; failed+=(25); }
# An attractor search needs 20 recorded periods; a Newton search that fails writes nothing.
expect 25 2 "run.periods: an attractor search records at least 20 periods" "$bin/gapchain-attractors" nm2.json --set run.periods=1 --samples 6 --no-plot --out a25
expect 25 1 "no orbit of period 3" "$bin/gapchain-orbit" nm2.json --period 3 --from-transient 0 --out o25.json
one_line 25
absent 25 a25 o25.json
# A failed run leaves a folder's previous content; a successful one leaves no file of another
# mode's earlier run (a basin slice next to a new attractor list).
"$bin/gapchain-attractors" nm2.json --samples 2 --grid u1,v1 --resolution 2 --out keep25 >/dev/null 2>&1
before=$(cat keep25/attractors.json keep25/basins.csv | md5sum)
expect 25 1 "keep25/basins.png: gnuplot could not write" env PATH="$dir/fakebin:$PATH" "$bin/gapchain-attractors" nm2.json --samples 3 --seed 2 --grid u1,v1 --resolution 3 --out keep25
[ "$(cat keep25/attractors.json keep25/basins.csv | md5sum)" = "$before" ] || { echo "class 25: FAIL: a failed run changed the folder"; failed+=(25); }
ls -a keep25 | grep -q staging && { echo "class 25: FAIL: a staging folder was left"; failed+=(25); }
gone=$(sh -c 'echo $$') # the pid of a process that has ended: its staging folder is stale
mkdir -p "keep25/.gapchain-staging.$gone"
expect 25 0 "" "$bin/gapchain-attractors" nm2.json --samples 2 --no-plot --out keep25
absent 25 keep25/basins.csv keep25/basins.png keep25/basins.gp "keep25/.gapchain-staging.$gone"
# Only files a run wrote are removed (the probe of 2026-11-26: a user's basins.csv went).
mkdir -p user25 && echo my,data >user25/basins.csv && echo mine >user25/fractions.gp
expect 25 0 "" "$bin/gapchain-attractors" nm2.json --samples 2 --no-plot --out user25
[ "$(cat user25/basins.csv)" = my,data ] && [ "$(cat user25/fractions.gp)" = mine ] || { echo "class 25: FAIL: a user's file was removed"; failed+=(25); }
# Another tool's run into the same folder keeps the list of what runs wrote there.
"$bin/gapchain-attractors" nm2.json --samples 2 --grid u1,v1 --resolution 2 --no-plot --out mix25 >/dev/null 2>&1
expect 25 0 "" "$bin/gapchain-bifurcation" nm2.json --steps 2 --transient 5 --record 20 --no-plot --out mix25
expect 25 0 "" "$bin/gapchain-attractors" nm2.json --samples 2 --no-plot --out mix25
absent 25 mix25/basins.csv
[ -s mix25/summary.csv ] || { echo "class 25: FAIL: another tool's output was removed"; failed+=(25); }
# An input kept in the output folder under a name the tool writes is refused, untouched; so is
# a folder named like an output, before the run (it failed the run once its work was done).
mkdir -p in25 && cp nm2.json in25/attractors.json
expect 25 2 "--out: in25/attractors.json is an input of this run" "$bin/gapchain-attractors" in25/attractors.json --samples 2 --out in25
cmp -s nm2.json in25/attractors.json || { echo "class 25: FAIL: the input in the folder changed"; failed+=(25); }
mkdir -p way25/attractors.json && echo old >way25/attractors.csv
expect 25 2 "way25/attractors.json is a folder named like a file this tool may write" "$bin/gapchain-attractors" nm2.json --samples 2 --no-plot --out way25
[ "$(cat way25/attractors.csv)" = old ] || { echo "class 25: FAIL: a failed run replaced attractors.csv"; failed+=(25); }
# stdout that cannot be written is a failure.
expect 25 1 "cannot write to standard output" sh -c "'$bin/gapchain-bounds' nm2.json >/dev/full"
verdict 25

# 26 (a later probe of 2026-11-24): a file output that is not a regular file (a pipe, a device, a
# symbolic link) was replaced by the atomic write's rename; a missing folder or an empty --out
# was found only after the run; a plot that cannot be written left the JSON and CSV behind.
small='{"model":{"Nm":3,"fc":100,"e_r":0.5},"excitation":{"f_r":1.0},"run":{"periods":50}}'
echo "$small" >s26.json
mkfifo fifo26 && ln -s "$dir/target26.json" link26
expect 26 2 "^gapchain-orbit: --out: fifo26 exists and is not a regular file" "$bin/gapchain-orbit" s26.json --out fifo26 && one_line 26
[ -p fifo26 ] || { echo "class 26: FAIL: the pipe was replaced"; failed+=(26); }
expect 26 2 "^gapchain-lyapunov: --out: link26 is a symbolic link" "$bin/gapchain-lyapunov" s26.json --out link26
[ -L link26 ] || { echo "class 26: FAIL: the link was replaced"; failed+=(26); }
expect 26 2 "^gapchain-sim: --trajectory: nodir26/t.csv: the folder .*nodir26 does not exist" "$bin/gapchain-sim" s26.json --trajectory nodir26/t.csv
expect 26 2 "^gapchain-orbit: --out: must name a file" "$bin/gapchain-orbit" s26.json --out ""
mkdir -p l26_convergence.png/x
expect 26 2 "--out \(its _convergence.png\): l26_convergence.png is a directory" "$bin/gapchain-lyapunov" s26.json --out l26.json
absent 26 l26.json l26_history.csv l26_convergence.gp
# A SIGTERM reaches Newton's shootings of a large row (one took 25 s before it was asked) and a
# work-precision study (it ran to its end): exit 143 long before the outer KILL, nothing written.
# (--foreground: timeout otherwise also signals its process group, and a second SIGTERM ends a
# tool at once, silently, by design.)
expect 26 143 "interrupted by SIGTERM" timeout -s KILL 20 timeout --foreground --preserve-status -s TERM 1 "$bin/gapchain-orbit" s26.json --set model.Nm=300 --scheme rk4 --from-transient 0 --out o26.json
# (The continuation and the grid are asked within their work limits: beyond them they are now
# refused before they run, helper-85.)
expect 26 143 "interrupted by SIGTERM" timeout -s KILL 20 timeout --foreground --preserve-status -s TERM 1 "$bin/gapchain-continue" s26.json --set model.Nm=300 --scheme rk4 --set run.max_work=1e12 --from 1 --to 1.1 --transient 0 --no-plot --out c26
expect 26 143 "interrupted by SIGTERM" timeout -s KILL 20 timeout --foreground --preserve-status -s TERM 1 "$bin/gapchain-accuracy" s26.json --periods 100000 --repeats 1 --no-unsplit --set run.max_work=1e15 --no-plot --out a26
expect 26 143 "interrupted by SIGTERM" timeout -s KILL 20 timeout --foreground --preserve-status -s TERM 1 "$bin/gapchain-modes" --grid --grid-fc-points 10 --grid-Nm-max 400 --out g26
absent 26 o26.json c26 a26 g26
# A row whose contacts never close is a valid answer, not a failed figure: an event section with
# no points and a flat spectrum write their CSV files and exit 0.
expect 26 0 "the section has no points: no figure" "$bin/gapchain-poincare" s26.json --set model.e_r=1e6 --section event --trigger g0 --level 0 --out p26
[ -f p26/section.csv ] || { echo "class 26: FAIL: no section.csv"; failed+=(26); }
expect 26 0 "no power at any frequency" "$bin/gapchain-spectrum" s26.json --set model.e_r=1e6 --variable F0 --segment 512 --out sp26
[ -f sp26/psd.csv ] || { echo "class 26: FAIL: no psd.csv"; failed+=(26); }
# A refusal gives the real limitation: orbit's tangent flow and accuracy's exact reference need
# the linear law (the old message pointed at a scheme that fails too), and bifurcation no longer
# sends nonlinear laws to gapchain-accuracy.
expect 26 2 "^gapchain-orbit: model.contact_law: gapchain-orbit needs the linear contact law" "$bin/gapchain-orbit" s26.json --set model.contact_law=hertz --out o26.json
expect 26 2 "^gapchain-accuracy: model.contact_law: gapchain-accuracy needs the linear contact law" "$bin/gapchain-accuracy" s26.json --set model.contact_law=hertz --out a26
expect 26 2 "nonlinear laws work in gapchain-sim, -sweep, -poincare and -spectrum$" "$bin/gapchain-bifurcation" s26.json --set model.contact_law=hertz --steps 2 --out b26
absent 26 o26.json a26 b26
# Input that would be ignored is refused: a scene or --set beside the paper's tables and eq
# (26)'s grid, a section option of the other kind of section.
expect 26 2 "scene excludes --table" "$bin/gapchain-bounds" /nonexistent.json --table --set bogus.key=1
expect 26 2 "scene excludes --grid" "$bin/gapchain-modes" /nonexistent.json --grid --set bogus=1
expect 26 2 "^gapchain-poincare: --phase: applies to --section stroboscopic only" "$bin/gapchain-poincare" s26.json --section event --phase 0.7 --out q26
expect 26 2 "^gapchain-poincare: --trigger: applies to --section event only" "$bin/gapchain-poincare" s26.json --trigger v2 --level 3 --out q26
absent 26 q26
# A plot that fails after the run puts back the previous results that the plot's inputs,
# written in place, had replaced (the second read's finding: they were deleted instead).
expect 26 0 "" "$bin/gapchain-lyapunov" s26.json --out lp26.json
before=$(cat lp26.json lp26_history.csv lp26_convergence.gp lp26_convergence.png | md5sum)
mkdir -p fail26 && printf '#!/bin/sh\ncat >/dev/null\nexit 1\n' >fail26/gnuplot && chmod +x fail26/gnuplot
expect 26 1 "gnuplot could not write the figure" env PATH="$dir/fail26:$PATH" "$bin/gapchain-lyapunov" s26.json --set run.periods=60 --out lp26.json
[ "$(cat lp26.json lp26_history.csv lp26_convergence.gp lp26_convergence.png | md5sum)" = "$before" ] || { echo "class 26: FAIL: a failed plot changed the previous results"; failed+=(26); }
ls | grep -q "gapchain-old" && { echo "class 26: FAIL: a set-aside file was left"; failed+=(26); }
verdict 26

# 27 (the probe of 2026-11-26, session 40): input that was silently ignored or cut, and a
# scene that hung.
# A --set of a run key the tool does not read changed nothing; it is refused, naming it.
expect 27 2 "--set run.step: gapchain-classify does not read it" "$bin/gapchain-classify" fig5.json --set run.step=0.001 --out c27.json
one_line 27
expect 27 2 "--set run.periods: gapchain-bifurcation does not read it" "$bin/gapchain-bifurcation" fig5.json --param f_r --from 1 --to 1.1 --steps 2 --set run.periods=5 --no-plot --out b27
expect 27 2 "--set output.trajectory_every: gapchain-lyapunov does not read it" "$bin/gapchain-lyapunov" fig5.json --set output.trajectory_every=7 --out l27.json
expect 27 2 "--set run.periods: gapchain-modes does not read it" "$bin/gapchain-modes" --set run.periods=3 --out m27.json
absent 27 c27.json b27 l27.json m27.json
# A key given twice inside a --set object value, as in a scene file.
expect 27 2 "model.scatter.seed: duplicate key" "$bin/gapchain-sim" fig5.json --set 'model.scatter={"clearance":0.3,"seed":3,"seed":4}' --out s27.json
# A NUL byte ended the scene: what followed it was dropped.
printf '{"model":{"Nm":5},"run":{"periods":50}}\000{"junk":' >nul27.json
expect 27 2 "nul27.json: a NUL byte at offset 39" "$bin/gapchain-sim" nul27.json --out s27.json
# A named pipe no one writes to blocked in open(), and the first interrupt only set a flag;
# a pipe with a writer is read.
mkfifo fifo27.json
expect 27 2 "fifo27.json: a pipe with nothing written to it" "$bin/gapchain-sim" fifo27.json --out s27.json
absent 27 s27.json
expect 27 0 "" sh -c "cat fig5.json | '$bin/gapchain-sim' /dev/stdin --set run.periods=20 -q --out s27.json"
expect 27 2 "/dev/zero: is a socket or device" "$bin/gapchain-sim" /dev/zero --out z27.json
absent 27 z27.json
verdict 27

# 28 (the probe of 2026-11-27, session 42): a crash, numbers read as something else, and
# keys silently dropped or ignored.
python3 -c "n=100000; print('{\"model\":{\"fc\":' + '['*n + ']'*n + '}}')" >deep28.json
expect 28 2 "deep28.json: model.fc: nested more than 64 levels deep" "$bin/gapchain-sim" deep28.json --out s28.json
one_line 28
echo '{"model": {"eps": 1e-999}}' >under28.json
expect 28 2 "model.eps: a number must be 0 or finite with \|x\| in \[2.2250738585072014e-308, 1.7976931348623157e308\] \(the normal doubles\), got \"1e-999\"" "$bin/gapchain-sim" under28.json --out s28.json
echo '{"model": {"fc": 4.9e-324}}' >sub28.json
expect 28 2 "model.fc: a number must be 0 or finite with .*got \"4.9e-324\"" "$bin/gapchain-sim" sub28.json --out s28.json
expect 28 2 "excitation.f_r: .*got 10000.000000000002" "$bin/gapchain-sim" fig5.json --set excitation.f_r=10000.000000000002 --out s28.json
expect 28 2 "--steps: from 3 to 3.0000000000000004 in 5 steps repeats a value" "$bin/gapchain-attractors" fig5.json --param f_r --from 3 --to 3.0000000000000004 --steps 5 --out a28
echo '{"model": {"fc": NaN}}' >nan28.json
expect 28 2 "model.fc: must be a finite number \(JSON has no NaN or Infinity\), got NaN" "$bin/gapchain-sim" nan28.json --out s28.json
expect 28 2 "--set model.scatter: overlaps --set model.scatter.seed" "$bin/gapchain-sim" fig5.json --set model.scatter.seed=2 --set 'model.scatter={"clearance":0.1}' --out s28.json
# Integers in base 0, hex floats and an empty text were numbers to CLI11.
expect 28 2 "--samples: must be a decimal integer, got \"0100\" \(a leading 0 would make it octal\)" "$bin/gapchain-attractors" fig5.json --samples 0100 --out a28
expect 28 2 "--from: must be a finite decimal number, got \"0x10\" \(hex is not read\)" "$bin/gapchain-continue" fig5.json --param f_r --from 0x10 --to 3 --out c28
expect 28 2 "--from: must be a finite decimal number, got \"\"" "$bin/gapchain-bifurcation" fig5.json --param f_r --from '' --to 3 --steps 2 --out b28
expect 28 2 "--Nm: must be a decimal integer" "$bin/gapchain-modes" --Nm 010 --out m28.json
expect 28 2 "--e_r: must be from:to:count" "$bin/gapchain-classify" fig5.json --map --e_r 0:0.1:4294967298 --f_r 3:3:1 --out k28
expect 28 2 "--e_r: must be from:to:count" "$bin/gapchain-classify" fig5.json --map --e_r 1e-999:0.1:2 --f_r 3:3:1 --out k28
# Keys a tool sets itself, or reads only with a flag, changed nothing.
expect 28 2 "--set run.estimate_error: gapchain-attractors does not read it" "$bin/gapchain-attractors" fig5.json --samples 2 --set run.estimate_error=false --out a28
expect 28 2 "--set output.trajectory_every: gapchain-sim without --trajectory does not read it" "$bin/gapchain-sim" fig5.json --set output.trajectory_every=5 --out s28.json
printf 'Nm,fc,eps,e_r,f_r,F_m,status\n2.9xyz,60,0.5,0.1,1,0.5,steady_state\n' >rows28.csv
expect 28 2 "rows28.csv line 2, Nm: must be a decimal integer" "$bin/gapchain-bench" relaxed rows28.csv
# classify --map's axes replace the scene's e_r and f_r: a --set of them changed nothing.
expect 28 2 "--set model.e_r: gapchain-classify --map varies e_r itself" "$bin/gapchain-classify" fig5.json --map --e_r 0.1:0.3:2 --f_r 0.5:1:2 --set model.e_r=0.7 --out k28
# A tolerance listed twice ran twice (duplicate rows).
expect 28 2 "--tolerances: 0.001 is listed twice" "$bin/gapchain-accuracy" fig5.json --tolerances 1e-3 1e-3 --out acc28
absent 28 acc28
# The once-through tools ran the same with run keys they do not read.
expect 28 2 "--set run.steady_state: gapchain-lyapunov does not read it" "$bin/gapchain-lyapunov" fig5.json --set run.steady_state=false --out l28.json
expect 28 2 "--set run.accuracy_mode: gapchain-spectrum does not read it" "$bin/gapchain-spectrum" fig5.json --set run.accuracy_mode=strict --out p28
expect 28 2 "--set run.estimate_error: gapchain-poincare does not read it" "$bin/gapchain-poincare" fig5.json --set run.estimate_error=false --out q28
absent 28 l28.json p28 q28
# A sweep axis over the number a model array replaces ran one row under each label.
echo '{"scene": {"model": {"Nm": 3, "clearance": [0.2, 0.2, 0.2, 0.2]}, "run": {"periods": 20}}, "parameters": {"e_r": [0.1, 3]}}' >arr28.json
expect 28 2 "parameters.e_r: not read where the scene's model.clearance" "$bin/gapchain-sweep" arr28.json --out arr28.csv
# ... and a single run printed e_r = 3 for a row whose clearances were all 0.2.
echo '{"model": {"Nm": 3, "clearance": [0.2, 0.2, 0.2, 0.2]}, "run": {"periods": 20}}' >arr28s.json
expect 28 2 "model.e_r: not read where model.clearance gives every entry" "$bin/gapchain-sim" arr28s.json --set model.e_r=3 --out arr28s.out.json
absent 28 arr28s.out.json
# A record scene's accelerogram was overwritten by --out naming it.
printf '0,0\n0.01,1\n0.02,-1\n0.03,0\n' >rec28.csv
cp rec28.csv rec28.keep
echo '{"units": "physical", "model": {"Nm": 2, "M": 100, "K": 1e5, "C": 500, "Kc": 5e7, "e": 0.003}, "excitation": {"type": "record", "file": "rec28.csv"}}' >rec28.json
expect 28 2 "--out: rec28.csv is an input of this run" "$bin/gapchain-sim" rec28.json --out rec28.csv
cmp -s rec28.csv rec28.keep || { echo "class 28: FAIL: the record file was changed"; failed+=(28); }
# gapchain-modes read the arrays at the scene's Nm before --Nm: 3 entries were refused for
# "must have 5", and 5 then for "must have 3".
expect 28 0 "" "$bin/gapchain-modes" fig5.json --Nm 3 --fc 60 --set 'model.mass=[1,2,1]' --out modes28.json
absent 28 arr28.csv k28
# A row out of the model's range names its file and line too; a line's end its option.
printf 'Nm,fc,eps,e_r,f_r,F_m,status\n5,-60,0.5,0.06,3,0.3,steady_state\n' >rows28c.csv
expect 28 2 "rows28c.csv line 2, model.fc: must be" "$bin/gapchain-bench" relaxed rows28c.csv
expect 28 2 "--from: excitation.f_r: one forcing period" "$bin/gapchain-continue" fig5.json --from 1e-300 --to 3 --out c28
expect 28 2 "--to: excitation.f_r: one forcing period" "$bin/gapchain-attractors" fig5.json --param f_r --from 3 --to 1e-300 --steps 3 --out a28
absent 28 s28.json a28 c28 b28 m28.json k28
# Decimals JSON does not spell are numbers in --set as on the command line (+0.5 was "not a
# number"); a study range that repeats a value is refused; a huge flag is not echoed whole.
expect 28 0 "" "$bin/gapchain-sim" fig5.json --set run.periods=20 --set model.eps=+0.5 -q --out s28.json
echo '{"scene": {"run": {"periods": 20}}, "parameters": {"e_r": {"lin": [0, 0, 2]}}}' >rep28.json
expect 28 2 "parameters.e_r: the range \[0, 0, 2\] repeats the value 0" "$bin/gapchain-sweep" rep28.json --out rep28.csv
absent 28 rep28.csv
"$bin/gapchain-sim" fig5.json --attractors 2 --seed "$(printf '1%.0s' $(seq 50000))" --out s28b.json 2>"$dir/long28" >/dev/null
[ "$(wc -c <"$dir/long28")" -lt 1000 ] || { echo "class 28: FAIL: a 50,000-digit --seed was echoed whole"; failed+=(28); }
# A full disk was "cannot write the output file: Success" (the stream kept no errno).
if mount -t tmpfs -o size=12k tmpfs full 2>/dev/null; then
    dd if=/dev/zero of=full/fill bs=1k count=4 2>/dev/null
    expect 28 1 "full/a28/starts.csv: cannot write the output file: No space left on device" "$bin/gapchain-attractors" fig5.json --samples 40 --set run.periods=40 --no-plot --out full/a28
    umount full
else
    echo "class 28: skipped the full-disk part (mount not permitted here)"
fi
# A sweep row that did not settle ends in an empty field, which the row reader dropped.
printf 'Nm,fc,eps,e_r,f_r,F_m,status,steady_state_period\n2,60,0.5,0.1,1,0.5,completed,\n2,60,0.5,0.1,1,0.65,steady_state,1\n' >rows28b.csv
expect 28 0 "" "$bin/gapchain-bench" relaxed rows28b.csv
# A long number flag overflowed the stack of the first number check (a regex).
expect 28 2 "--from: must be a finite decimal number" "$bin/gapchain-bifurcation" fig5.json --from "1.$(printf '1%.0s' $(seq 50000))x" --to 3 --steps 2 --out b28
# K M below the doubles' range: eps is still C / (2 sqrt(K M)) = 5.
expect 28 0 "" "$bin/gapchain-sim" "$scenes/table4-experiment-harmonic.json" --set model.K=1e-200 --set model.Kc=1e-195 --set model.C=1e-199 --set model.M=1e-200 --set excitation.f=1e-3 --set run.periods=20 -q --out s28.json
verdict 28

# 29 (session 45's probe): a trajectory past what memory or disk holds passed the work check;
# an ill-formed UTF-8 byte reached the message raw (Python raised an empty ValueError); a row
# of clearances was titled with the default e_r.
echo '{"model": {"Nm": 3, "fc": 100, "eps": 0.3, "e_r": 0.2}, "excitation": {"f_r": 1.3}, "run": {"periods": 300}}' >s29.json
expect 29 2 "output.trajectory_every: the trajectory would hold about .* at most 250000000 values" "$bin/gapchain-sim" s29.json --trajectory t29.csv --set run.periods=10000000 --set run.steady_state=false --out s29.out.json
absent 29 t29.csv s29.out.json
printf '{"model": {"Nm": 2}, "run": {"periods": 50}, "x": "\xff"}' >utf29.json
expect 29 2 "ill-formed UTF-8 byte; last read: '.{1,2}xFF'$" "$bin/gapchain-sim" utf29.json --out u29.json
expect 29 0 "" "$bin/gapchain-accuracy" s29.json --set 'model.clearance=[0.2,0.2,0.2,0.2]' --schemes rk4 --periods 5 --repeats 1 --no-plot --out acc29
grep -q "e_r=array" "$dir/stdout" || { echo "class 29: FAIL: gapchain-accuracy did not title the row e_r=array"; failed+=(29); }
# gapchain-modes and modes() took the forcing and the start, and ignored them.
expect 29 2 "--set excitation.f_r: gapchain-modes does not read it" "$bin/gapchain-modes" --set excitation.f_r=2 --out m29.json
absent 29 m29.json
verdict 29

# 30 (session 52's probe): a flag that changes nothing, a shard with a leading zero, a sweep
# axis value given twice, a study axis over a text key, and a sweep whose comparison runs are
# above run.max_work (it left a header-only CSV and sidecar).
expect 30 2 "--no-unsplit: only rk4 and central_difference run without switch splitting" "$bin/gapchain-accuracy" s29.json --schemes exact --no-unsplit --periods 5 --repeats 1 --no-plot --out acc30
absent 30 acc30
echo '{"scene": {"model": {"Nm": 2}, "run": {"periods": 20}}, "parameters": {"e_r": [0.1, 0.2]}}' >st30.json
expect 30 2 "--shard: must be i/n" "$bin/gapchain-sweep" st30.json --shard 0/02 --out r30.csv
echo '{"scene": {"model": {"Nm": 2}, "run": {"periods": 20}}, "parameters": {"e_r": [0.1, 0.1]}}' >twice30.json
expect 30 2 "parameters.e_r: the value 0.1 is given twice" "$bin/gapchain-sweep" twice30.json --out r30.csv
echo '{"scene": {"model": {"Nm": 2}, "run": {"periods": 20}}, "parameters": {"scheme": ["rk4", "exact"]}}' >text30.json
expect 30 2 "parameters.scheme: cannot be swept" "$bin/gapchain-sweep" text30.json --out r30.csv
echo '{"scene": {"model": {"Nm": 2, "eps": 0.5, "fc": 60}, "excitation": {"f_r": 3.0}, "run": {"periods": 40, "transient_periods": 20, "max_work": 5000}}, "parameters": {"e_r": [0.05, 0.1]}}' >work30.json
expect 30 2 "run.max_work: the error estimate's comparison run" "$bin/gapchain-sweep" work30.json --out r30.csv
absent 30 r30.csv r30.csv.json
verdict 30

if [ "${#failed[@]}" -eq 0 ]; then
    echo "all 30 classes checked"
    exit 0
fi
exit 1
