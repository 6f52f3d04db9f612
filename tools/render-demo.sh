#!/usr/bin/env bash
# The main job: install, build (Release) and render a benchmark scene to a PNG through the
# GLES kernels on EGL (a GPU where there is one, Mesa's llvmpipe where there is none).
# Usage: tools/render-demo.sh [scene] [extra raystream-render flags...]; default cow17.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/tools/deps.sh"
build=${RS_BUILD_DIR:-$root/build}
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DRS_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" -j"$(nproc)" --target raystream-render >/dev/null
scene=${1:-cow17}
shift || true
mkdir -p "$root/out"
"$build/tools/render/raystream-render" --scene "$scene" --backend egl --bvh sah --passes 2 \
  --lights 1 --size 512x512 --out "$root/out/$scene.png" --stats "$root/out/$scene.json" "$@"
