#!/usr/bin/env bash
# Runs every tool over the shipped scenes and studies (studies on a stratified subset of their
# points) and writes the outputs under OUT. Two builds' outputs compare with
#   python3 tools/dev/compare_outputs.py OUT_BEFORE OUT_AFTER
# which ignores wall times and PNG files. Used to show that a refactoring changes no result.
#   bash tools/dev/regression_outputs.sh BUILD_BIN_DIR OUT [SUBSET]
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=$(cd "$1" && pwd)
out=$2
subset=${3:-12}
mkdir -p "$out"
out=$(cd "$out" && pwd)
scenes="$root/data/scenes"
short=(--set run.periods=60)

# Each command's exit status and stdout go into OUT/<name>.log.
step() {
    local name=$1
    shift
    (cd "$root" && "$@" >"$out/$name.log" 2>"$out/$name.err")
    echo "exit $?" >>"$out/$name.log"
}

for scene in "$scenes"/*.json; do
    s=$(basename "$scene" .json)
    step "sim-$s" "$bin/gapchain-sim" "$scene" --out "$out/sim-$s.json"
    step "bounds-$s" "$bin/gapchain-bounds" "$scene"
done
step sim-fig5-traj "$bin/gapchain-sim" "$scenes/fig5.json" "${short[@]}" \
    --set output.trajectory_every=7 --trajectory "$out/sim-fig5-traj.csv" --out "$out/sim-fig5-traj.json"
for scheme in rk4 central_difference rkf45 rk8pd exact; do
    step "sim-fig13-$scheme" "$bin/gapchain-sim" "$scenes/fig13.json" --set run.scheme=$scheme \
        --set excitation.f_r=2.6 --set run.periods=300 --out "$out/sim-fig13-$scheme.json"
done
step bounds-table "$bin/gapchain-bounds" --table
step bif-ind "$bin/gapchain-bifurcation" --steps 16 --transient 60 --record 20 --threads 2 \
    --no-plot --out "$out/bif-ind"
step bif-cont "$bin/gapchain-bifurcation" --steps 12 --transient 60 --record 20 \
    --mode continuation --no-plot --out "$out/bif-cont"
step poincare "$bin/gapchain-poincare" "$scenes/fig13.json" --set excitation.f_r=3.3 \
    --set run.periods=300 --record u1 v1 g0 F0 --no-plot --out "$out/poincare"
step poincare-event "$bin/gapchain-poincare" "$scenes/fig13.json" --set excitation.f_r=2.6 \
    --set run.periods=260 --section event --trigger u1 --no-plot --out "$out/poincare-event"
step modes "$bin/gapchain-modes" --Nm 7 --fc 60 --out "$out/modes.json" --csv "$out/modes.csv"
step modes-sparse "$bin/gapchain-modes" --Nm 2000 --fc 100 --modes 4 --method sparse \
    --out "$out/modes-sparse.json"
step modes-grid "$bin/gapchain-modes" --grid --grid-fc-points 8 --grid-Nm-max 6 \
    --out "$out/modes-grid"
step classify "$bin/gapchain-classify" "$scenes/fig13.json" --set excitation.f_r=2.6 \
    --out "$out/classify.json"
step classify-map "$bin/gapchain-classify" "$scenes/fig13.json" --map --e_r 0:1:4 --f_r 0.5:3:4 \
    --transient 40 --record 60 --threads 2 --no-plot --out "$out/classify-map"
step lyapunov "$bin/gapchain-lyapunov" "$scenes/fig13.json" --set excitation.f_r=2.6 \
    --set run.periods=260 --no-plot --out "$out/lyapunov.json"
step spectrum "$bin/gapchain-spectrum" "$scenes/fig13.json" --set excitation.f_r=2.6 \
    --set run.periods=400 --segment 1024 --no-plot --out "$out/spectrum"
step accuracy "$bin/gapchain-accuracy" "$scenes/fig5.json" --periods 20 --repeats 1 \
    --tolerances 1e-3 1e-5 --no-plot --out "$out/accuracy"
for study in "$root"/data/studies/*.json; do
    s=$(basename "$study" .json)
    step "sweep-$s" "$bin/gapchain-sweep" "$study" --subset "$subset" --threads 2 \
        --out "$out/sweep-$s.csv"
done
echo "outputs in $out"
