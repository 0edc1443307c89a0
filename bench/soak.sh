#!/usr/bin/env bash
# The soak benchmark (not CI): MINUTES (default 30) of the real-time farm under tracer and
# client churn and injected link faults; see bench/soak.py. Results under bench/results.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
if [ -z "${BUILD:-}" ]; then
  "$root/scripts/install_deps.sh"
  "$root/scripts/build.sh" "$root/build/release" -DPATHFARM_BUILD_TESTS=OFF -DPATHFARM_BUILD_BENCH=ON
fi
python3 "$root/bench/soak.py" --build "${BUILD:-$root/build/release}" --minutes "${MINUTES:-30}" "$@"
