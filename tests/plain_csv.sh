#!/usr/bin/env bash
# Every CSV the tools write is plain tidy CSV: one header line, then rows with as many fields as
# the header, no comment or blank lines. Usage: plain_csv.sh BIN_DIR SOURCE_DIR
set -u
bin=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cd "$dir" || exit 1
scene="$src/data/scenes/fig13.json"
short=(--set run.periods=60 --set run.transient_periods=20)
run() { "$@" >/dev/null 2>&1 || { echo "FAIL: $*"; exit 1; }; }
mkdir -p sim lyapunov modes sweep
run "$bin/gapchain-sim" "$scene" "${short[@]}" --trajectory sim/trajectory.csv --out sim/r.json
run "$bin/gapchain-bifurcation" --steps 4 --transient 20 --record 10 --no-plot --out bif
run "$bin/gapchain-poincare" "$scene" "${short[@]}" --no-plot --out poincare
run "$bin/gapchain-spectrum" "$scene" --set run.periods=300 --segment 512 --no-plot --out spectrum
run "$bin/gapchain-lyapunov" "$scene" "${short[@]}" --no-plot --out lyapunov/l.json
run "$bin/gapchain-classify" "$scene" --map --e_r 0:1:3 --f_r 1:3:3 --transient 20 --record 20 --no-plot --out map
run "$bin/gapchain-accuracy" "$src/data/scenes/fig5.json" --periods 10 --repeats 1 --schemes rk4 exact --tolerances 1e-3 1e-5 --no-plot --out accuracy
run "$bin/gapchain-modes" --Nm 4 --fc 30 --csv modes/shapes.csv --out modes/m.json
run "$bin/gapchain-modes" --grid --grid-fc-points 4 --grid-Nm-max 3 --out grid
run "$bin/gapchain-sweep" "$src/tests/scenes/small-study.json" --subset 6 --out sweep/results.csv
fail=0
count=0
while IFS= read -r csv; do
    count=$((count + 1))
    if ! awk -F, 'NR == 1 { n = NF; if (NF < 1 || $0 ~ /^#/) bad = 1; next }
                  $0 ~ /^#/ || $0 == "" || NF != n { bad = 1; print FILENAME ": line " NR ": " $0; exit }
                  END { exit bad }' "$csv"; then
        echo "FAIL: $csv is not plain CSV"
        fail=1
    fi
done < <(find . -name '*.csv')
echo "$count CSV files checked"
[ "$count" -ge 10 ] || { echo "FAIL: expected at least 10 CSV files"; fail=1; }
[ "$fail" -eq 0 ] && echo "every CSV is plain"
exit $fail
