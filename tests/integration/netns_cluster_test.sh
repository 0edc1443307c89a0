#!/usr/bin/env bash
# Multi-host test: coordinator and two tracers in separate network namespaces render frames,
# first without link delay, then with 20 ms on every link. Skipped (exit 77) with a message
# when namespaces or netem are unavailable; the no-delay run still proves the multi-host path
# whenever namespaces exist.
set -uo pipefail
build="$1"
root="$(cd "$(dirname "$0")/../.." && pwd)"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
"$root/deploy/netns/cluster.sh" "$build" "$out/plain" --tracers 2 --frames 4 > "$out/plain.txt" 2>&1
rc=$?
cat "$out/plain.txt"
[ "$rc" -eq 77 ] && { echo "SKIP: network namespaces unavailable"; exit 77; }
[ "$rc" -ne 0 ] && { echo "FAIL: multi-host farm without delay (exit $rc)"; tail -5 "$out/plain/coordinator.log"; exit 1; }
grep -q "frames=4 " "$out/plain.txt" || { echo "FAIL: expected 4 frames"; exit 1; }
"$root/deploy/netns/cluster.sh" "$build" "$out/delay" --tracers 2 --frames 4 --delay-ms 20 > "$out/delay.txt" 2>&1
rc=$?
cat "$out/delay.txt"
[ "$rc" -eq 78 ] && { echo "SKIP: netem unavailable; the multi-host farm ran without delay only"; exit 77; }
[ "$rc" -ne 0 ] && { echo "FAIL: multi-host farm with 20 ms delay (exit $rc)"; exit 1; }
grep -q "frames=4 " "$out/delay.txt" || { echo "FAIL: expected 4 frames with delay"; exit 1; }
echo "PASS: 2 tracers in namespaces, with and without 20 ms link delay"
