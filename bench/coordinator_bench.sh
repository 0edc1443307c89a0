#!/usr/bin/env bash
# Builds the release tree with benchmarks and runs bench/coordinator_bench.py.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install_deps.sh"
"$root/scripts/build.sh" "$root/build/release" -DPATHFARM_BUILD_TESTS=OFF -DPATHFARM_BUILD_BENCH=ON
exec python3 "$root/bench/coordinator_bench.py" "$@"
