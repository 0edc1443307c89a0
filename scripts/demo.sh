#!/usr/bin/env bash
# The main job: install what is missing, build, and run the farm on loopback: a coordinator,
# two tracers and a headless client on builtin:default, in real time: the game runs (moving
# ball, switching light, the client turning and pressing the action key), frames converge,
# and workload scaling holds TARGET_FPS. Prints the frame rate, the quality chosen, each
# tracer's utilisation and the client's input latency, and writes the frames (JPEG) and a
# contact sheet to out/.
# Environment: FRAMES (default 100), WIDTH x HEIGHT (320x180), SPP (max, 4), TARGET_FPS (10),
# BACKENDS (the two tracers' backends, default "embree embree"; "embree opencl" mixes them),
# SCENE (default builtin:default), OUT (default out/), BIN (a build tree to run instead of building build/release: A/B runs,
# bench/demo_ab.py), COORDINATOR_ARGS (more coordinator arguments, e.g. "--denoise off"),
# TRACER_ARGS (more tracer arguments, e.g. "--log-level debug"), TRACER_NICE (the tracers'
# nice value, default 10: they share this machine's cores with the coordinator, whose display
# stage is on the way from an input to the screen; 0 to compare), HTTP_PORT (the browser
# client's port, default 0: any; its URL is printed).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
if [ -z "${BIN:-}" ]; then
  "$root/scripts/install_deps.sh"
  "$root/scripts/build.sh" "$root/build/release" -DPATHFARM_BUILD_TESTS=OFF -DPATHFARM_BUILD_BENCH=ON
fi
bin="${BIN:-$root/build/release}"
out="${OUT:-$root/out}"
frames="${FRAMES:-100}" width="${WIDTH:-320}" height="${HEIGHT:-180}" spp="${SPP:-4}"
target="${TARGET_FPS:-10}"
rm -rf "$out" && mkdir -p "$out/frames"
export PATHFARM_SECRET="${PATHFARM_SECRET:-$(head -c 32 /dev/urandom | od -An -tx1 | tr -d ' \n')}"

pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT
trap 'exit 143' TERM  # so that the EXIT trap stops the farm when the demo is stopped
trap 'exit 130' INT

"$bin/coordinator/pathfarm-coordinator" --scene "${SCENE:-builtin:default}" --tracer-port 0 --client-port 0 \
  --width "$width" --height "$height" --spp "$spp" --frames "$frames" --min-tracers 2 \
  --target-fps "$target" --fps "$target" --http-port "${HTTP_PORT:-0}" \
  --stats-csv "$out/stats.csv" --tracer-stats-csv "$out/tracers.csv" --stages-csv "$out/stages.csv" \
  ${COORDINATOR_ARGS:-} > "$out/coordinator.log" 2>&1 &
coordinator=$!
pids+=("$coordinator")
for _ in $(seq 100); do grep -q "tracer_port=" "$out/coordinator.log" && break; sleep 0.1; done
tracer_port=$(grep -o "tracer_port=[0-9]*" "$out/coordinator.log" | cut -d= -f2)
client_port=$(grep -o "client_port=[0-9]*" "$out/coordinator.log" | cut -d= -f2)
grep -o "browser client: .*" "$out/coordinator.log" | sed 's/^/demo: /' || true
"$bin/client/pathfarm-client" --connect "127.0.0.1:$client_port" --headless --frames "$frames" \
  --turn-rate 0.1 --action-every-second --latency-csv "$out/latency.csv" \
  --out "$out/frames" --contact-sheet "$out/contact_sheet.png" > "$out/client.log" 2>&1 &
client=$!
pids+=("$client")
for _ in $(seq 100); do grep -q '"headless-client" connected' "$out/coordinator.log" && break; sleep 0.1; done
read -r -a backends <<< "${BACKENDS:-embree embree}"
names=(tracer-a tracer-b)
tracers=()
for i in 0 1; do
  "$bin/tracer-node/pathfarm-tracer" --coordinator "127.0.0.1:$tracer_port" --name "${names[$i]}" \
    --backend "${backends[$i]:-embree}" --threads 1 --max-reconnects 0 --nice "${TRACER_NICE:-10}" \
    ${TRACER_ARGS:-} > "$out/${names[$i]}.log" 2>&1 &
  pids+=($!)
  tracers+=($!)
done
# A tracer that ends before the run does (a bad TRACER_ARGS, a crash) would leave the
# coordinator waiting for it for ever: say which one and why. Waits for whichever ends first
# rather than polling: a loop of grep and sleep every 0.2 s took 2-3 % of the two cores the
# farm runs on.
coordinator_status=""
running=("${tracers[@]}")  # tracers not yet reaped: bash's wait names a reaped one an error
while [ -z "$coordinator_status" ]; do
  ended="" status=0
  wait -n -p ended "$coordinator" "${running[@]}" || status=$?
  if [ "$ended" = "$coordinator" ] || [ -z "$ended" ]; then
    coordinator_status=$status
    continue
  fi
  left=()
  for p in "${running[@]}"; do [ "$p" = "$ended" ] || left+=("$p"); done
  running=("${left[@]}")
  if ! grep -q "fps=" "$out/coordinator.log"; then
    for i in 0 1; do
      if [ "$ended" = "${tracers[$i]}" ]; then
        echo "demo: ${names[$i]} stopped before the run ended:"; tail -5 "$out/${names[$i]}.log"; exit 1
      fi
    done
  fi
done
[ "$coordinator_status" = 0 ] || { echo "demo: the coordinator failed:"; tail -5 "$out/coordinator.log"; exit 1; }
wait "$client" || { echo "demo: the client failed:"; tail -5 "$out/client.log"; exit 1; }

grep "fps=" "$out/coordinator.log" | sed 's/^/coordinator: /'
grep "fps=\|latency_p50" "$out/client.log" | sed 's/^/client:      /'
awk -F, 'NR > 1 { spp += $7; w += $9; h += $10; n++ }
  END { if (n) printf "quality: mean %.2f spp at %.0fx%.0f (workload scaling)\n", spp / n, w / n, h / n }' \
  "$out/stats.csv"
seconds=$(grep -o "seconds=[0-9.]*" "$out/coordinator.log" | cut -d= -f2)
awk -F, -v s="$seconds" 'NR > 1 { ms[$2] += $5; up[$2] += $7; n[$2]++ }
  END { for (t in ms) printf "%s: %d frames, utilisation %.0f%% of %.2f s rendering, %.1f%% updating the scene\n",
        t, n[t], 100 * ms[t] / 1000 / s, s, 100 * up[t] / 1000 / s }' \
  "$out/tracers.csv" | sort
echo "demo: wrote $out/frames/ ($(ls "$out/frames" | wc -l) frames), $out/contact_sheet.png, $out/stats.csv"
