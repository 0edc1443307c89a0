#!/usr/bin/env bash
# Configures (once) and builds a build tree. Usage: scripts/build.sh BUILD_DIR [cmake options...]
# TARGETS="a b" limits the build to those targets.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$1"; shift
export CCACHE_DIR="${CCACHE_DIR:-$root/.ccache}"
if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@"
else
  cmake "$build" "$@" >/dev/null
fi
cmake --build "$build" ${TARGETS:+--target $TARGETS}
