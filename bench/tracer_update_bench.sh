#!/usr/bin/env bash
# Builds the release tree and runs bench/tracer_update_bench.py.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install_deps.sh"
"$root/scripts/build.sh" "$root/build/release" -DPATHFARM_BUILD_TESTS=OFF -DPATHFARM_BUILD_BENCH=ON
exec python3 "$root/bench/tracer_update_bench.py" "$@"
