#!/usr/bin/env bash
# Configures (once) and builds a build tree. Usage: scripts/build.sh BUILD_DIR [cmake options...]
# TARGETS="a b" limits the build to those targets.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$1"; shift
export CCACHE_DIR="${CCACHE_DIR:-$root/.ccache}"
# The test targets' precompiled headers (tests/support/precompiled.h) are cached only when
# ccache may ignore their build-time macros and fresh timestamps.
export CCACHE_SLOPPINESS="${CCACHE_SLOPPINESS:-pch_defines,time_macros,include_file_mtime,include_file_ctime}"
if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@"
else
  cmake "$build" "$@" >/dev/null
fi
cmake --build "$build" ${TARGETS:+--target $TARGETS}
