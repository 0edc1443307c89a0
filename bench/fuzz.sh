#!/usr/bin/env bash
# Runs every libFuzzer target for at least RUNS executions (default 10^6) from its committed
# seeds, in the clang + ASan + UBSan tree of scripts/test.sh (BUILD, default build/sanitize),
# and writes per target the executions, coverage (edges, features), corpus size, seconds and
# crashes to bench/results/fuzz.csv. A crash stops that target and leaves its input in
# BUILD/crashes/<target>/: once fixed, copy it into tests/fuzz/regressions/<target>/, where
# ctest runs it from then on. Not CI (CI runs each target for seconds).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
runs="${RUNS:-1000000}"
build="${BUILD:-$root/build/sanitize}"
"$root/scripts/install_deps.sh"
# The options of scripts/test.sh's sanitizer tree: the same tree serves both.
CC=clang CXX=clang++ TARGETS="pathfarm_fuzz_targets" "$root/scripts/build.sh" "$build" \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPATHFARM_SANITIZE=ON \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" -DPATHFARM_FUZZ=ON \
  -DPATHFARM_WITH_EMBREE=OFF -DPATHFARM_WITH_OPENCL=OFF -DPATHFARM_WERROR=ON
csv="$root/bench/results/fuzz.csv"
echo "target,executions,edges,features,corpus,seconds,crashes" > "$csv"
for exe in "$build"/tests/fuzz/pathfarm-fuzz-*; do
  name="${exe##*/pathfarm-fuzz-}"
  [ "$name" = seeds ] && continue
  work="$build/fuzz-work/$name" crashes="$build/crashes/$name"
  mkdir -p "$work" "$crashes"
  start=$(date +%s.%N)
  status=0
  "$exe" -runs="$runs" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
    -artifact_prefix="$crashes/" "$work" "$root/tests/fuzz/corpus/$name" > "$work.log" 2>&1 || status=$?
  seconds=$(echo "$(date +%s.%N) - $start" | bc)
  execs=$(grep -o "stat::number_of_executed_units: *[0-9]*" "$work.log" | grep -o "[0-9]*$" || echo 0)
  edges=$(grep -o "cov: [0-9]*" "$work.log" | tail -1 | grep -o "[0-9]*" || echo 0)
  features=$(grep -o "ft: [0-9]*" "$work.log" | tail -1 | grep -o "[0-9]*" || echo 0)
  corpus=$(ls "$work" | wc -l)
  found=$(ls "$crashes" | wc -l)
  [ "$status" -ne 0 ] && [ "$found" -eq 0 ] && found=1  # a failure without an artifact
  printf "%s,%s,%s,%s,%s,%.1f,%s\n" "$name" "$execs" "$edges" "$features" "$corpus" "$seconds" "$found" | tee -a "$csv"
done
echo "fuzz: $csv"
