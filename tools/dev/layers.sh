#!/usr/bin/env bash
# Checks that lib/ includes follow ARCHITECTURE.md's layer order: a file includes only headers
# of strictly lower layers (or its own header); detail/ headers are private helpers, exempt.
# Layers: model -> dynamics -> integrators -> run -> observers (sections are observers) ->
# analyses -> composite analyses (classify weighs exponents and spectra; bounds uses the exact
# linear-chain frequency) -> sweep (drives analyses) -> scene I/O (scene, study, report).
# Exit 1 and the offending lines if any. Usage: bash tools/dev/layers.sh
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$root/lib"
declare -A layer=(
    [model]=0 [ground_motion]=0 [grid]=0 [spectrum]=0
    [dynamics]=1
    [stepper]=2 [exact_propagator]=2 [gsl_stepper]=2
    [run]=3
    [observers]=4 [poincare]=4 [tangent_flow]=4
    [simulation]=5 [signal]=5 [lyapunov]=5 [modes]=5 [accuracy]=5 [bifurcation]=5 [orbit]=5
    [classify]=6 [bounds]=6 [continuation]=6
    [attractors]=7
    [sweep]=8
    [scene]=9 [study]=10 [report]=11
)
bad=0
for f in include/gapchain/*.hpp src/*.cpp; do
    name=$(basename "$f"); name=${name%.*}
    [ -n "${layer[$name]+x}" ] || { echo "$f: no layer assigned"; bad=1; continue; }
    while IFS= read -r inc; do
        [ "$inc" = "$name" ] && continue
        [ -n "${layer[$inc]+x}" ] || { echo "$f: includes $inc, which has no layer"; bad=1; continue; }
        if [ "${layer[$inc]}" -ge "${layer[$name]}" ]; then
            echo "$f (layer ${layer[$name]}) includes $inc (layer ${layer[$inc]})"
            bad=1
        fi
    done < <(grep -o '#include "gapchain/[a-z_]*' "$f" | sed 's|#include "gapchain/||')
done
[ "$bad" -eq 0 ] && echo "includes follow the layer order"
exit $bad
