#!/usr/bin/env bash
# scripts/demo.sh, the README's first command, run on an existing build tree (BIN): a short run
# ends with its summary and its frames, its tracers below the coordinator's priority, and a
# tracer that cannot start (an unknown flag in TRACER_ARGS) makes it fail at once, naming the
# tracer and the flag, instead of leaving the coordinator waiting for it for ever.
# Usage: demo_script_test.sh <source dir> <build dir>
set -uo pipefail
src="$1" bin="$2"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "demo_script_test: $*"; exit 1; }

out="$(BIN="$bin" OUT="$tmp/ok" FRAMES=8 timeout 60 bash "$src/scripts/demo.sh" 2>&1)" ||
  fail "the short demo failed: $out"
grep -q "^demo: wrote" <<< "$out" || fail "no summary line: $out"
# bash's own complaints ("scripts/demo.sh: line 66: wait: 123: no such job") are the script's
# bugs, even when the run succeeds.
! grep -q "demo.sh: line [0-9]*:" <<< "$out" || fail "the script itself complained: $out"
grep -q "^tracer-a: 8 frames" <<< "$out" || fail "tracer-a rendered other than 8 frames: $out"
# The tracers share the machine with the coordinator: they run below it (TRACER_NICE).
grep -q "running at nice 10" "$tmp/ok/tracer-a.log" || fail "tracer-a not niced: $(head -3 "$tmp/ok/tracer-a.log")"
frames="$(ls "$tmp/ok/frames" | wc -l)"
[ "$frames" -eq 8 ] || fail "$frames frames written, 8 expected"

start=$SECONDS
out="$(BIN="$bin" OUT="$tmp/bad" FRAMES=8 TRACER_ARGS="--no-such-flag" timeout 30 \
  bash "$src/scripts/demo.sh" 2>&1)"
rc=$?
[ "$rc" -ne 124 ] || fail "a tracer that cannot start left the demo hanging"
[ "$rc" -ne 0 ] || fail "a tracer that cannot start went unnoticed: $out"
grep -q "tracer-[ab] stopped before the run ended" <<< "$out" || fail "no tracer named: $out"
grep -q -- "--no-such-flag" <<< "$out" || fail "the tracer's own error is not shown: $out"
echo "demo_script_test: ok (the failing run ended after $((SECONDS - start)) s)"
