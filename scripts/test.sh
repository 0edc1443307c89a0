#!/usr/bin/env bash
# The whole test suite: install what is missing, build with warnings as errors, run every test
# (format, layering, unit, render, integration), then the unit tests of the pure libraries again
# under AddressSanitizer + UndefinedBehaviorSanitizer.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
jobs="$(nproc)"
# Each phase's wall time, so that the CI budget (25 minutes) can be watched phase by phase.
phase_start=$SECONDS
phase() { echo "== $1 (the phase before took $((SECONDS - phase_start)) s)"; phase_start=$SECONDS; }
"$root/scripts/install_deps.sh"

phase "build (Release, -Werror)"
# Strict: Embree and OpenCL (PoCL) must be found, so that their tests cannot silently vanish.
"$root/scripts/build.sh" "$root/build/ci" -DPATHFARM_WERROR=ON -DPATHFARM_BUILD_TESTS=ON \
  -DPATHFARM_BUILD_BENCH=ON -DPATHFARM_STRICT_OPTIONS=ON
phase "tests"
ctest --test-dir "$root/build/ci" -j "$jobs" --output-on-failure --timeout 120

phase "build: pure libraries under ASan + UBSan, and the fuzz targets (clang)"
# One clang tree for both: libFuzzer needs clang, and clang's UBSan checks more than GCC's
# (it found a null-pointer offset GCC's did not). -O1 -g1 (line tables): ASan's recommended
# level and stack traces with lines, at half the compile time of -O2 -g.
CC=clang CXX=clang++ \
TARGETS="pathfarm_unit_tests pathfarm_coordinator_tests pathfarm_balance_sim_tests pathfarm_fuzz_targets" \
  "$root/scripts/build.sh" "$root/build/sanitize" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPATHFARM_SANITIZE=ON \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" -DPATHFARM_FUZZ=ON \
  -DPATHFARM_WITH_EMBREE=OFF -DPATHFARM_WITH_OPENCL=OFF -DPATHFARM_WERROR=ON
phase "sanitizer and fuzz tests"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir "$root/build/sanitize" -j "$jobs" -L "pure|fuzz" --output-on-failure --timeout 300
echo "== done (the sanitizer tests took $((SECONDS - phase_start)) s; $SECONDS s in all)"
