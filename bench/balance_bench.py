#!/usr/bin/env python3
"""Balancing benchmark (issue: workload balancing): Brigade's Table 1 and ours simulated on the
recorded Sponza traces (pathfarm-balance-sim), and the live farm with 2 tracers of unequal
speed (one with --slowdown 1.7) over 128 frames of Sponza on the slow camera path, per scheme:
mean idle % and frame time. CSV and plots under bench/results."""
import argparse
import csv
import os
import statistics
import subprocess
import tempfile

from bench_common import ROOT, SCENES, wait_for, write_csv, batch_mode
from bench_common import run as run_tool

SCHEMES = ["none", "robin-hood", "perfect", "perfect-smooth", "cost-predictive"]
TRACES = os.path.join(ROOT, "tools", "balance-sim", "traces")


def live(build, scheme, frames, work, hiccup_p=0.0):
    os.environ["PATHFARM_SECRET"] = "balance-bench"
    log = os.path.join(work, "coordinator.log")
    stats = os.path.join(work, "stats.csv")
    coordinator = subprocess.Popen(
        [f"{build}/coordinator/pathfarm-coordinator", "--scene", f"{SCENES}/dabrovic-sponza/sponza.obj", "--tracer-port",
         "0", "--client-port", "0", "--width", "320", "--height", "180", "--spp", "4", "--frames", str(frames),
         "--min-tracers", "2", "--balancer", scheme, "--stats-csv", stats, *batch_mode(f"{build}/coordinator/pathfarm-coordinator")], stdout=open(log, "w"), stderr=subprocess.STDOUT)
    ports = wait_for(log, r"tracer_port=(\d+) client_port=(\d+)", "balance_bench")
    client = subprocess.Popen([f"{build}/client/pathfarm-client", "--connect", f"127.0.0.1:{ports.group(2)}", "--headless",
                               "--frames", str(frames), "--script", os.path.join(TRACES, "slow_path.txt")],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wait_for(log, '"headless-client" connected', "balance_bench")
    tracers = [subprocess.Popen([f"{build}/tracer-node/pathfarm-tracer", "--coordinator", f"127.0.0.1:{ports.group(1)}",
                                 "--threads", "1", "--name", name, "--max-reconnects", "0"] + extra,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
               for name, extra in (("fast", ["--hiccup-p", str(hiccup_p), "--hiccup-seed", "1"]),
                                   ("slow", ["--slowdown", "1.7", "--hiccup-p", str(hiccup_p), "--hiccup-seed", "2"]))]
    coordinator.wait(timeout=1800)
    for p in tracers + [client]:
        p.wait(timeout=60)
    rows = list(csv.DictReader(open(stats)))[8:]  # skip warm-up (the scripted camera, first measurements)
    frame_ms = sorted(float(r["frame_ms"]) for r in rows)
    return {"idle_pct": round(statistics.mean(float(r["idle_pct"]) for r in rows), 2),
            "median_frame_ms": round(statistics.median(frame_ms), 1),
            "mean_frame_ms": round(statistics.mean(frame_ms), 1),
            "p95_frame_ms": round(frame_ms[min(len(frame_ms) - 1, int(0.95 * len(frame_ms)))], 1)}


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--frames", type=int, default=128)
    p.add_argument("--no-live", action="store_true")
    p.add_argument("--schemes", default=",".join(SCHEMES), help="live schemes, comma-separated")
    p.add_argument("--hiccup-p", type=float, default=0.0,
                   help="live: each tracer renders a frame 2x slower with this probability")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    table = run_tool([f"{a.build}/tools/pathfarm-balance-sim", "--tracers", "2,3", "--camera", "slow,fast", "--frames",
                      "128", "--schemes", "all", "--csv", os.path.join(a.out, "balance_sim.csv"), "--plot",
                      os.path.join(a.out, "balance_sim.png")], "balance_bench", with_stderr=False)
    print(table)
    if a.no_live:
        return
    rows = []
    for scheme in a.schemes.split(","):
        with tempfile.TemporaryDirectory() as work:
            m = live(a.build, scheme, a.frames, work, a.hiccup_p)
        rows.append([scheme] + list(m.values()))
        print(f"live 2 tracers (1.0, 1/1.7), hiccup p {a.hiccup_p}: {scheme:16} idle {m['idle_pct']:5.1f} %  frame ms "
              f"median {m['median_frame_ms']:6.1f} mean {m['mean_frame_ms']:6.1f} p95 {m['p95_frame_ms']:6.1f}", flush=True)
    name = "balance_live.csv" if a.hiccup_p == 0.0 else f"balance_live_hiccup{a.hiccup_p:g}.csv"
    write_csv(os.path.join(a.out, name), ["scheme", "idle_pct", "median_frame_ms", "mean_frame_ms", "p95_frame_ms"],
              rows)

if __name__ == "__main__":
    main()
