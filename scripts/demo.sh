#!/usr/bin/env bash
# The main job: install what is missing, build, and run the farm on loopback: a coordinator,
# two tracers and a headless client on builtin:default. Prints the frame rate and each
# tracer's utilisation, and writes the frames and a contact sheet to out/.
# Environment: FRAMES (default 60), WIDTH x HEIGHT (640x360), SPP (4).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install_deps.sh"
"$root/scripts/build.sh" "$root/build/release" -DPATHFARM_BUILD_TESTS=OFF -DPATHFARM_BUILD_BENCH=ON
bin="$root/build/release"
out="$root/out"
frames="${FRAMES:-60}" width="${WIDTH:-640}" height="${HEIGHT:-360}" spp="${SPP:-4}"
rm -rf "$out" && mkdir -p "$out/frames"
export PATHFARM_SECRET="${PATHFARM_SECRET:-$(head -c 32 /dev/urandom | od -An -tx1 | tr -d ' \n')}"

pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT

"$bin/coordinator/pathfarm-coordinator" --scene builtin:default --tracer-port 0 --client-port 0 \
  --width "$width" --height "$height" --spp "$spp" --frames "$frames" --min-tracers 2 \
  --stats-csv "$out/stats.csv" --tracer-stats-csv "$out/tracers.csv" > "$out/coordinator.log" 2>&1 &
coordinator=$!
for _ in $(seq 100); do grep -q "tracer_port=" "$out/coordinator.log" && break; sleep 0.1; done
tracer_port=$(grep -o "tracer_port=[0-9]*" "$out/coordinator.log" | cut -d= -f2)
client_port=$(grep -o "client_port=[0-9]*" "$out/coordinator.log" | cut -d= -f2)
"$bin/client/pathfarm-client" --connect "127.0.0.1:$client_port" --headless --frames "$frames" \
  --out "$out/frames" --contact-sheet "$out/contact_sheet.png" > "$out/client.log" 2>&1 &
client=$!
for _ in $(seq 100); do grep -q '"headless-client" connected' "$out/coordinator.log" && break; sleep 0.1; done
for name in tracer-a tracer-b; do
  "$bin/tracer-node/pathfarm-tracer" --coordinator "127.0.0.1:$tracer_port" --name "$name" --threads 1 \
    --max-reconnects 0 > "$out/$name.log" 2>&1 &
  pids+=($!)
done
wait "$coordinator" || { echo "demo: the coordinator failed:"; tail -5 "$out/coordinator.log"; exit 1; }
wait "$client" || { echo "demo: the client failed:"; tail -5 "$out/client.log"; exit 1; }

grep "fps=" "$out/coordinator.log" | sed 's/^/coordinator: /'
grep "fps=" "$out/client.log" | sed 's/^/client:      /'
seconds=$(grep -o "seconds=[0-9.]*" "$out/coordinator.log" | cut -d= -f2)
awk -F, -v s="$seconds" 'NR > 1 { ms[$2] += $5; n[$2]++ }
  END { for (t in ms) printf "%s: %d frames, utilisation %.0f%% of %.2f s\n", t, n[t], 100 * ms[t] / 1000 / s, s }' \
  "$out/tracers.csv" | sort
echo "demo: wrote $out/frames/ ($(ls "$out/frames" | wc -l) frames), $out/contact_sheet.png, $out/stats.csv"
