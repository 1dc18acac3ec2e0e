#!/usr/bin/env bash
# An interrupted basin-fraction line, bifurcation diagram, branch continuation, regime map or
# work-precision study keeps what it had done: the values it reported on stdout, the rows that
# ran, the orbits found, the cells classified, the runs measured; it exits 130 (SIGINT) or 143
# (SIGTERM), draws no plot and leaves no staging folder.
# Usage: interrupt_keeps_done.sh BIN_DIR SCENE_DIR
set -u
bin=$1
scenes=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
failed() { echo "FAIL: $*"; fail=1; }
# interrupt_after SECONDS SIGNAL NAME COMMAND...: runs COMMAND (stdout, stderr to NAME.out,
# NAME.err), sends SIGNAL after SECONDS, and sets rc to its exit status.
interrupt_after() {
    local seconds=$1 signal=$2 name=$3
    shift 3
    "$@" >"$dir/$name.out" 2>"$dir/$name.err" &
    local pid=$!
    sleep "$seconds"
    kill "-$signal" "$pid"
    wait "$pid"
    rc=$?
}
# No staging folder of an interrupted run is left in OUT.
no_staging() { ! ls -A "$1" | grep -q '^\.gapchain-staging'; }

# 1. A long basin-fraction line, interrupted once it has reported two values done.
"$bin/gapchain-attractors" "$scenes/fig13.json" --param f_r --from 3.0 --to 3.4 --steps 400 \
    --samples 8 --set run.periods=300 --out "$dir/line" >"$dir/line.out" 2>"$dir/line.err" &
pid=$!
for _ in $(seq 1 1200); do
    [ "$(grep -c ' of 400)' "$dir/line.out")" -ge 2 ] && break
    sleep 0.05
done
kill -INT "$pid"
wait "$pid"
rc=$?
reported=$(grep -c ' of 400)' "$dir/line.out")
rows=$(($(wc -l <"$dir/line/fractions.csv") - 1))
echo "line: exit $rc, $reported values reported, $rows rows kept"
[ "$rc" -eq 130 ] || failed "line: exit $rc, not 130"
[ "$reported" -ge 2 ] && [ "$reported" -lt 400 ] || failed "line: $reported values reported"
[ "$rows" -eq "$reported" ] || failed "line: $rows rows kept for $reported values reported"
grep -q '"cancelled": true' "$dir/line/fractions.json" || failed "line: fractions.json not marked cancelled"
[ ! -e "$dir/line/fractions.png" ] || failed "line: a plot of an interrupted line"
grep -q "kept what was done: the $reported of 400 values" "$dir/line.err" || failed "line: message: $(cat "$dir/line.err")"
no_staging "$dir/line" || failed "line: staging folder left"

# 2. An independent bifurcation diagram far too long to finish, interrupted (SIGTERM) after 4 s.
interrupt_after 4 TERM diagram "$bin/gapchain-bifurcation" --from 2 --to 4 --steps 200000 \
    --transient 50 --record 20 --out "$dir/diagram"
ran=$(tail -n +2 "$dir/diagram/summary.csv" | grep -vc ',cancelled,')
cancelled=$(tail -n +2 "$dir/diagram/summary.csv" | grep -c ',cancelled,')
echo "diagram: exit $rc, $ran rows ran, $cancelled cancelled"
[ "$rc" -eq 143 ] || failed "diagram: exit $rc, not 143"
[ "$ran" -ge 1 ] && [ "$cancelled" -ge 1 ] || failed "diagram: $ran rows ran, $cancelled cancelled"
# Every row that ran has its section points in points.csv.
[ "$(tail -n +2 "$dir/diagram/points.csv" | cut -d, -f1 | sort -u | wc -l)" -eq "$ran" ] ||
    failed "diagram: points.csv does not hold the $ran rows that ran"
grep -q '"cancelled": true' "$dir/diagram/bifurcation.json" || failed "diagram: JSON not marked cancelled"
[ ! -e "$dir/diagram/bifurcation.png" ] || failed "diagram: a plot of an interrupted diagram"
grep -q "kept what was done: $ran of 200000 rows done" "$dir/diagram.err" || failed "diagram: message: $(cat "$dir/diagram.err")"
no_staging "$dir/diagram" || failed "diagram: staging folder left"

# 3. A continuation in steps far too small to finish, interrupted after 4 s.
interrupt_after 4 INT branch "$bin/gapchain-continue" "$scenes/fig13.json" --from 2 --to 4 \
    --step 1e-5 --max-step 1e-5 --max-points 1000000 --out "$dir/branch"
orbits=$(($(wc -l <"$dir/branch/branch.csv") - 1))
echo "continuation: exit $rc, $orbits orbits kept"
[ "$rc" -eq 130 ] || failed "continuation: exit $rc, not 130"
[ "$orbits" -ge 1 ] || failed "continuation: no orbit kept"
grep -q "kept what was done: $orbits orbits" "$dir/branch.err" || failed "continuation: message: $(cat "$dir/branch.err")"
[ ! -e "$dir/branch/branch.png" ] || failed "continuation: a plot of an interrupted branch"
no_staging "$dir/branch" || failed "continuation: staging folder left"

# 4. The default regime map (10,000 cells), interrupted after 4 s.
interrupt_after 4 INT map "$bin/gapchain-classify" "$scenes/fig13.json" --map --out "$dir/map"
cells=$(($(wc -l <"$dir/map/map.csv") - 1))
echo "map: exit $rc, $cells cells kept"
[ "$rc" -eq 130 ] || failed "map: exit $rc, not 130"
[ "$cells" -ge 1 ] && [ "$cells" -lt 10000 ] || failed "map: $cells cells kept"
grep -q "kept what was done: $cells of 10000 cells done" "$dir/map.err" || failed "map: message: $(cat "$dir/map.err")"
[ ! -e "$dir/map/regimes.png" ] || failed "map: a plot of an interrupted map"
no_staging "$dir/map" || failed "map: staging folder left"

# 5. A work-precision study of 2000-period runs (minutes), interrupted after 4 s.
interrupt_after 4 INT accuracy "$bin/gapchain-accuracy" "$scenes/fig13.json" --periods 2000 \
    --repeats 1 --out "$dir/accuracy"
runs=$(($(wc -l <"$dir/accuracy/work_precision.csv") - 1))
echo "work-precision study: exit $rc, $runs runs kept"
[ "$rc" -eq 130 ] || failed "accuracy: exit $rc, not 130"
[ "$runs" -ge 1 ] || failed "accuracy: no run kept"
grep -q "kept what was done: $runs runs done" "$dir/accuracy.err" || failed "accuracy: message: $(cat "$dir/accuracy.err")"
[ ! -e "$dir/accuracy/work_precision.png" ] || failed "accuracy: a plot of an interrupted study"
no_staging "$dir/accuracy" || failed "accuracy: staging folder left"

[ "$fail" -eq 0 ] && echo "interrupt checks passed"
exit "$fail"
