#!/usr/bin/env bash
# The main job: install what is missing, build, and render the built-in default scene.
# Prints time, samples/s and rays/s and writes out/default.png (display) and out/default.exr
# (linear radiance). Extra arguments go to pathfarm-render (e.g. --spp 256 --width 1280).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install_deps.sh"
"$root/scripts/build.sh" "$root/build/release" -DPATHFARM_BUILD_TESTS=OFF -DPATHFARM_BUILD_BENCH=ON
mkdir -p "$root/out"
render="$root/build/release/tools/pathfarm-render"
"$render" --scene builtin:default --width 640 --height 360 --spp 64 --out "$root/out/default.exr" "$@"
"$render" --scene builtin:default --width 640 --height 360 --spp 64 --out "$root/out/default.png" --log-level warn "$@"
echo "demo: wrote $root/out/default.exr and $root/out/default.png"
