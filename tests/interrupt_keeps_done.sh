#!/usr/bin/env bash
# An interrupted basin-fraction line, bifurcation diagram, branch continuation, regime map or
# work-precision study keeps what it had done: the values it reported on stderr, the rows that
# ran, the orbits found, the cells classified, the runs measured; it exits 130 (SIGINT) or 143
# (SIGTERM), draws no plot and leaves no staging folder. So does a run interrupted while gnuplot
# draws its figure, and so does any finished run interrupted while it draws its figure (an
# attractor search's basin slice, a Poincare section), and a section interrupted while it
# estimates its points' error.
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
# interrupt_when CONDITION NAME COMMAND...: runs COMMAND (stdout, stderr to NAME.out, NAME.err),
# sends SIGINT once the shell test CONDITION holds (or the run has ended), and sets rc.
interrupt_when() {
    local condition=$1 name=$2
    shift 2
    "$@" >"$dir/$name.out" 2>"$dir/$name.err" &
    local pid=$!
    for _ in $(seq 1 1200); do
        eval "$condition" && break
        kill -0 "$pid" 2>/dev/null || break
        sleep 0.05
    done
    kill -INT "$pid"
    wait "$pid"
    rc=$?
}
# kept_checks NAME EXIT MESSAGE PLOT: the run NAME exited EXIT, its stderr says "kept what was
# done: MESSAGE", its folder has no PLOT, no gnuplot script and no staging folder left.
kept_checks() {
    local name=$1 exit_expected=$2 message=$3 plot=$4
    [ "$rc" -eq "$exit_expected" ] || failed "$name: exit $rc, not $exit_expected"
    grep -q "kept what was done: $message" "$dir/$name.err" || failed "$name: message: $(cat "$dir/$name.err")"
    [ ! -e "$dir/$name/$plot" ] || failed "$name: a plot of an interrupted run"
    ! ls "$dir/$name" | grep -q '\.gp$' || failed "$name: a gnuplot script of an interrupted run"
    ! ls -A "$dir/$name" | grep -q '^\.gapchain-staging' || failed "$name: staging folder left"
}

# 1. A long basin-fraction line, interrupted once it has reported two values done (on stderr).
interrupt_when '[ "$(grep -c " of 400)" "$dir/line.err")" -ge 2 ]' line \
    "$bin/gapchain-attractors" "$scenes/fig13.json" --param f_r --from 3.0 --to 3.4 --steps 400 \
    --samples 8 --set run.periods=300 --out "$dir/line"
reported=$(grep -c ' of 400)' "$dir/line.err")
rows=$(($(wc -l <"$dir/line/fractions.csv") - 1))
echo "line: exit $rc, $reported values reported, $rows rows kept"
[ "$reported" -ge 2 ] && [ "$reported" -lt 400 ] || failed "line: $reported values reported"
[ "$rows" -eq "$reported" ] || failed "line: $rows rows kept for $reported values reported"
grep -q '"cancelled": true' "$dir/line/fractions.json" || failed "line: fractions.json not marked cancelled"
kept_checks line 130 "the $reported of 400 values" fractions.png

# 2. An independent bifurcation diagram far too long to finish, interrupted (SIGTERM) after 4 s.
interrupt_after 4 TERM diagram "$bin/gapchain-bifurcation" --from 2 --to 4 --steps 200000 \
    --transient 50 --record 20 --out "$dir/diagram"
ran=$(($(wc -l <"$dir/diagram/summary.csv") - 1))
echo "diagram: exit $rc, $ran rows kept"
[ "$ran" -ge 1 ] && [ "$ran" -lt 200000 ] || failed "diagram: $ran rows kept"
! grep -q ',cancelled,' "$dir/diagram/summary.csv" || failed "diagram: a row not run was written"
# points.csv holds the rows of summary.csv, no row stopped part-way.
[ "$(tail -n +2 "$dir/diagram/points.csv" | cut -d, -f1 | sort -u | wc -l)" -eq "$ran" ] ||
    failed "diagram: points.csv does not hold the $ran rows of summary.csv"
grep -q "\"rows_done\": $ran," "$dir/diagram/bifurcation.json" || failed "diagram: rows_done is not $ran"
grep -q '"cancelled": true' "$dir/diagram/bifurcation.json" || failed "diagram: JSON not marked cancelled"
kept_checks diagram 143 "$ran of 200000 rows done" bifurcation.png

# 3. A continuation in steps far too small to finish, interrupted after 4 s.
interrupt_after 4 INT branch "$bin/gapchain-continue" "$scenes/fig13.json" --from 2 --to 4 \
    --step 1e-5 --max-step 1e-5 --max-points 1000000 --set run.max_work=1e12 --out "$dir/branch"
orbits=$(($(wc -l <"$dir/branch/branch.csv") - 1))
echo "continuation: exit $rc, $orbits orbits kept"
[ "$orbits" -ge 1 ] || failed "continuation: no orbit kept"
grep -q "\"orbits\": $orbits," "$dir/branch/continuation.json" || failed "continuation: JSON orbits is not $orbits"
grep -q '"cancelled": true' "$dir/branch/continuation.json" || failed "continuation: JSON not marked cancelled"
kept_checks branch 130 "$orbits orbits" branch.png

# 4. The default regime map (10,000 cells), interrupted after 4 s.
interrupt_after 4 INT map "$bin/gapchain-classify" "$scenes/fig13.json" --map --out "$dir/map"
cells=$(($(wc -l <"$dir/map/map.csv") - 1))
echo "map: exit $rc, $cells cells kept"
[ "$cells" -ge 1 ] && [ "$cells" -lt 10000 ] || failed "map: $cells cells kept"
kept_checks map 130 "$cells of 10000 cells done" regimes.png

# 5. A work-precision study of 2000-period runs (minutes), interrupted after 4 s.
interrupt_after 4 INT accuracy "$bin/gapchain-accuracy" "$scenes/fig13.json" --periods 2000 \
    --repeats 1 --out "$dir/accuracy"
runs=$(($(wc -l <"$dir/accuracy/work_precision.csv") - 1))
echo "work-precision study: exit $rc, $runs runs kept"
[ "$runs" -ge 1 ] || failed "accuracy: no run kept"
kept_checks accuracy 130 "$runs runs done" work_precision.png

# 6. A short line interrupted while gnuplot (a stand-in that waits) draws its figure: both
# values are kept, no figure.
mkdir "$dir/slow"
printf '#!/bin/sh\ntouch "%s/slow/started"\nexec sleep 60\n' "$dir" >"$dir/slow/gnuplot"
chmod +x "$dir/slow/gnuplot"
# interrupt_while_plotting NAME COMMAND...: runs COMMAND with the stand-in gnuplot and sends
# SIGINT once that has started.
interrupt_while_plotting() {
    local name=$1
    shift
    rm -f "$dir/slow/started"
    interrupt_when '[ -e "$dir/slow/started" ]' "$name" env PATH="$dir/slow:$PATH" "$@"
}
interrupt_while_plotting plotted "$bin/gapchain-attractors" "$scenes/fig13.json" --param f_r \
    --from 3.0 --to 3.01 --steps 2 --samples 8 --set run.periods=300 --out "$dir/plotted"
echo "line interrupted while plotting: exit $rc, $(($(wc -l <"$dir/plotted/fractions.csv") - 1)) rows kept"
[ "$(($(wc -l <"$dir/plotted/fractions.csv") - 1))" -eq 2 ] || failed "plotted: the two values not kept"
kept_checks plotted 130 "all 2 values" fractions.png

# 7. A single-point search with a basin slice, interrupted while gnuplot draws the slice: the
# whole search is kept, no figure.
interrupt_while_plotting slice "$bin/gapchain-attractors" "$scenes/fig13.json" --samples 4 \
    --grid u1,v1 --resolution 3 --set run.periods=300 --out "$dir/slice"
echo "search interrupted while plotting: exit $rc"
for f in attractors.csv attractors.json starts.csv basins.csv; do
    [ -s "$dir/slice/$f" ] || failed "slice: $f not kept"
done
[ "$(($(wc -l <"$dir/slice/basins.csv") - 1))" -eq 9 ] || failed "slice: basins.csv has not the 9 cells"
kept_checks slice 130 "the whole search, in $dir/slice (no figure)" basins.png

# 8. A finished Poincare section interrupted while gnuplot draws it: section.csv kept (before,
# the whole run was dropped), no figure, exit 130.
interrupt_while_plotting section "$bin/gapchain-poincare" "$scenes/fig13.json" \
    --set run.periods=300 --out "$dir/section"
echo "section interrupted while plotting: exit $rc"
[ -s "$dir/section/section.csv" ] || failed "section: section.csv not kept"
[ "$rc" -eq 130 ] || failed "section: exit $rc, not 130"
grep -q "once the run was done: its outputs were kept" "$dir/section.err" || failed "section: message: $(cat "$dir/section.err")"
[ ! -e "$dir/section/section.png" ] || failed "section: a plot of an interrupted run"
! ls "$dir/section" | grep -q '\.gp$' || failed "section: a gnuplot script of an interrupted run"

# 9. A Poincare section interrupted during its point error estimate (a finer run, after the
# section is written): the section is kept with point_error not estimated, exit 130 (before,
# the whole folder was dropped).
interrupt_when 'ls "$dir"/estimate/.gapchain-staging.*/section.csv >/dev/null 2>&1' estimate \
    "$bin/gapchain-poincare" "$scenes/fig13.json" --set run.periods=1200 --set run.scheme=rkf45 \
    --set run.tolerance=1e-10 --no-plot --out "$dir/estimate"
echo "section interrupted during its error estimate: exit $rc"
[ "$rc" -eq 130 ] || failed "estimate: exit $rc, not 130"
[ "$(($(wc -l <"$dir/estimate/section.csv") - 1))" -eq 1000 ] || failed "estimate: section.csv not whole"
grep -q '"not_estimated": "the finer run ended cancelled"' "$dir/estimate/section.json" ||
    failed "estimate: section.json: $(cat "$dir/estimate/section.json")"

[ "$fail" -eq 0 ] && echo "interrupt checks passed"
exit "$fail"
