#!/usr/bin/env bash
# The long numerical-stability run: the stress tests of tests/render/stress_test.cpp with
# 1000 random scenes (or STRESS_CASES), built with ASan + UBSan and Embree, in build/stress.
# Prints the gtest summary; exits non-zero on any failure or sanitizer report.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install_deps.sh"
TARGETS=pathfarm_render_tests "$root/scripts/build.sh" "$root/build/stress" \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPATHFARM_SANITIZE=ON -DPATHFARM_WITH_EMBREE=ON
export PATHFARM_STRESS_CASES="${STRESS_CASES:-1000}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# Embree's own allocator is not instrumented; leaks inside it are not ours.
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
start=$(date +%s)
"$root/build/stress/tests/pathfarm_render_tests" \
  --gtest_filter='Fuzz*:*ScaleInvariance*:LargeCoordinates*:Degenerate*:HardTransport*:LongAccumulation*'
echo "stress: ${PATHFARM_STRESS_CASES} random scenes and the stress suite passed under ASan+UBSan in $(( $(date +%s) - start )) s"
