#!/usr/bin/env bash
# Paths that go into the gnuplot scripts the tools run: a control character is refused before
# any work (exit 2, no file; a newline in --out or --overlay ran `system(...)`, a hostile probe,
# helper-85), and a quote is written twice, so "it's.json" plots. Usage: plot_paths.sh BIN SCENE
set -u
bin=$1
scene=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
cd "$dir" || exit 1
bad=$'q\nsystem("touch PWNED")\n#.json'
"$bin/gapchain-lyapunov" "$scene" --out "$bad" >out.txt 2>&1
rc=$?
[ "$rc" -eq 2 ] || { echo "FAIL lyapunov control character: exit $rc"; fail=1; }
grep -q -- "--out: the path holds a control character" out.txt ||
    { echo "FAIL lyapunov control character: message"; cat out.txt; fail=1; }
[ -e PWNED ] && { echo "FAIL lyapunov: the script ran a command"; fail=1; }
[ "$(ls | wc -l)" -eq 1 ] || { echo "FAIL lyapunov control character: files left"; ls; fail=1; }
"$bin/gapchain-bifurcation" "$scene" --from 2 --to 3 --steps 4 --no-plot --out bf >/dev/null 2>&1 ||
    { echo "FAIL bifurcation for the overlay"; fail=1; }
overlay_dir=$'o\nsystem("touch PWNED")\n#'
mkdir -p "$overlay_dir" "o'q" && cp bf/summary.csv bf/bifurcation.json "$overlay_dir/" &&
    cp bf/summary.csv bf/bifurcation.json "o'q/"
"$bin/gapchain-continue" "$scene" --from 2 --to 3 --overlay "$overlay_dir/summary.csv" \
    --out c1 >out.txt 2>&1
rc=$?
[ "$rc" -eq 2 ] || { echo "FAIL continue control character: exit $rc"; fail=1; }
[ -e PWNED ] && { echo "FAIL continue: the script ran a command"; fail=1; }
[ -e c1 ] && { echo "FAIL continue control character: c1 left"; fail=1; }
if command -v gnuplot >/dev/null; then
    "$bin/gapchain-lyapunov" "$scene" --out "it's.json" >out.txt 2>&1 ||
        { echo "FAIL lyapunov with a quote"; cat out.txt; fail=1; }
    [ -s "it's_convergence.png" ] || { echo "FAIL lyapunov with a quote: no figure"; fail=1; }
    "$bin/gapchain-continue" "$scene" --from 2 --to 3 --overlay "o'q/summary.csv" \
        --out c2 >out.txt 2>&1 || { echo "FAIL continue with a quote"; cat out.txt; fail=1; }
    [ -s c2/branch.png ] || { echo "FAIL continue with a quote: no figure"; fail=1; }
    # A template value that is gnuplot code, not text, broke when quotes were doubled (the
    # diagram's "title 'sweep down'", a reread, helper-86): the continuation mode's figure.
    "$bin/gapchain-bifurcation" "$scene" --from 2 --to 3 --steps 4 --mode continuation \
        --out bc >out.txt 2>&1 || { echo "FAIL bifurcation continuation figure"; cat out.txt; fail=1; }
    [ -s bc/bifurcation.png ] || { echo "FAIL bifurcation continuation: no figure"; fail=1; }
else
    echo "note: gnuplot not found; the figure checks were skipped"
fi
[ "$fail" -eq 0 ] && echo "plot path checks passed"
exit "$fail"
