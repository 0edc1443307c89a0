#!/usr/bin/env bash
# Runs the farm as separate hosts on one machine: the coordinator and each tracer in their own
# network namespace, joined by veth pairs to a bridge in a "switch" namespace, with optional
# delay and loss on every link (tc netem). Addresses live only inside these namespaces.
#
#   deploy/netns/cluster.sh BUILD_DIR OUT_DIR [--tracers N] [--delay-ms D] [--loss-pct L] [--frames F]
#
# Prints the coordinator's summary line. Exit 77 when namespaces (root, iproute2) are
# unavailable; exit 78 when netem is unavailable but a delay or loss was asked for.
set -euo pipefail
build="$1"; out="$2"; shift 2
tracers=2 delay=0 loss=0 frames=10
while [ $# -gt 0 ]; do
  case "$1" in
    --tracers) tracers="$2"; shift 2 ;;
    --delay-ms) delay="$2"; shift 2 ;;
    --loss-pct) loss="$2"; shift 2 ;;
    --frames) frames="$2"; shift 2 ;;
    *) echo "cluster.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
prefix="pf$$"
sw="${prefix}-sw"
hosts=("${prefix}-co")
for i in $(seq 1 "$tracers"); do hosts+=("${prefix}-t$i"); done

if [ "$(id -u)" -ne 0 ] || ! ip netns add "$sw" 2>/dev/null; then
  echo "cluster.sh: network namespaces unavailable (needs root and iproute2)"; exit 77
fi
cleanup() {
  for h in "${hosts[@]}"; do ip netns pids "$h" 2>/dev/null | xargs -r kill 2>/dev/null || true; ip netns del "$h" 2>/dev/null || true; done
  ip netns del "$sw" 2>/dev/null || true
}
trap cleanup EXIT
ip -n "$sw" link add br0 type bridge
ip -n "$sw" link set br0 up
netem_ok=1
n=1
for h in "${hosts[@]}"; do
  ip netns add "$h"
  ip link add "v$n" netns "$h" type veth peer name "p$n" netns "$sw"
  ip -n "$sw" link set "p$n" master br0 up
  ip -n "$h" addr add "10.77.0.$n/24" dev "v$n"
  ip -n "$h" link set "v$n" up
  ip -n "$h" link set lo up
  if [ "$delay" != 0 ] || [ "$loss" != 0 ]; then
    ip netns exec "$h" tc qdisc add dev "v$n" root netem delay "${delay}ms" loss "${loss}%" 2>/dev/null || netem_ok=0
  fi
  n=$((n + 1))
done
if [ "$netem_ok" = 0 ]; then
  echo "cluster.sh: tc netem unavailable (kernel module sch_netem missing): cannot add ${delay} ms delay / ${loss}% loss"; exit 78
fi
mkdir -p "$out"
export PATHFARM_SECRET="${PATHFARM_SECRET:-netns-cluster-secret}"
ip netns exec "${hosts[0]}" "$build/coordinator/pathfarm-coordinator" --scene builtin:default --bind 10.77.0.1 \
  --tracer-port 7400 --client-port 7401 --width 160 --height 90 --spp 2 --frames "$frames" --min-tracers "$tracers" --fixed-spp \
  --stats-csv "$out/stats.csv" --dump-frames "$out/dump" > "$out/coordinator.log" 2>&1 &
coordinator=$!
for i in $(seq 1 "$tracers"); do
  ip netns exec "${hosts[$i]}" "$build/tracer-node/pathfarm-tracer" --coordinator 10.77.0.1:7400 --name "host$i" \
    --threads 1 --max-reconnects 20 > "$out/tracer$i.log" 2>&1 &
done
wait "$coordinator"
grep "fps=" "$out/coordinator.log"
