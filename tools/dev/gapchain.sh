#!/usr/bin/env bash
# The README's two commands. Each installs what is missing, configures and builds as needed.
#   bash tools/dev/gapchain.sh demo   runs the main job on a built-in default
#   bash tools/dev/gapchain.sh test   runs the whole test suite
#   bash tools/dev/gapchain.sh build  only builds (into ./build)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build="${GAPCHAIN_BUILD_DIR:-$root/build}"
jobs=$(nproc 2>/dev/null || echo 2)
bash "$root/tools/dev/deps.sh"
if [ ! -f "$build/CMakeCache.txt" ]; then
    cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build" -j"$jobs" >/dev/null
case "${1:-demo}" in
    build) ;;
    test) cd "$build" && ctest -j"$jobs" --output-on-failure ;;
    demo)
        out="${2:-$root/out/fig13}"
        "$build/bin/gapchain-bifurcation" --out "$out" ;;
    *) echo "usage: $0 demo|test|build" >&2; exit 2 ;;
esac
