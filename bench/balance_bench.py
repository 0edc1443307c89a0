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

from bench_common import ROOT, SCENES, wait_for, write_csv
from bench_common import run as run_tool

SCHEMES = ["none", "robin-hood", "perfect", "perfect-smooth", "cost-predictive"]
TRACES = os.path.join(ROOT, "tools", "balance-sim", "traces")


def live(build, scheme, frames, work):
    os.environ["PATHFARM_SECRET"] = "balance-bench"
    log = os.path.join(work, "coordinator.log")
    stats = os.path.join(work, "stats.csv")
    coordinator = subprocess.Popen(
        [f"{build}/coordinator/pathfarm-coordinator", "--scene", f"{SCENES}/dabrovic-sponza/sponza.obj", "--tracer-port",
         "0", "--client-port", "0", "--width", "320", "--height", "180", "--spp", "4", "--frames", str(frames),
         "--min-tracers", "2", "--balancer", scheme, "--stats-csv", stats], stdout=open(log, "w"), stderr=subprocess.STDOUT)
    ports = wait_for(log, r"tracer_port=(\d+) client_port=(\d+)", "balance_bench")
    client = subprocess.Popen([f"{build}/client/pathfarm-client", "--connect", f"127.0.0.1:{ports.group(2)}", "--headless",
                               "--frames", str(frames), "--script", os.path.join(TRACES, "slow_path.txt")],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wait_for(log, '"headless-client" connected', "balance_bench")
    tracers = [subprocess.Popen([f"{build}/tracer-node/pathfarm-tracer", "--coordinator", f"127.0.0.1:{ports.group(1)}",
                                 "--threads", "1", "--name", name, "--max-reconnects", "0"] + extra,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
               for name, extra in (("fast", []), ("slow", ["--slowdown", "1.7"]))]
    coordinator.wait(timeout=1800)
    for p in tracers + [client]:
        p.wait(timeout=60)
    rows = list(csv.DictReader(open(stats)))[8:]  # skip warm-up (the scripted camera, first measurements)
    return statistics.mean(float(r["idle_pct"]) for r in rows), statistics.median(float(r["frame_ms"]) for r in rows)


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--frames", type=int, default=128)
    p.add_argument("--no-live", action="store_true")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    table = run_tool([f"{a.build}/tools/pathfarm-balance-sim", "--tracers", "2,3", "--camera", "slow,fast", "--frames",
                      "128", "--schemes", "all", "--csv", os.path.join(a.out, "balance_sim.csv"), "--plot",
                      os.path.join(a.out, "balance_sim.png")], "balance_bench", with_stderr=False)
    print(table)
    if a.no_live:
        return
    rows = []
    for scheme in SCHEMES:
        with tempfile.TemporaryDirectory() as work:
            idle, frame_ms = live(a.build, scheme, a.frames, work)
        rows.append([scheme, round(idle, 2), round(frame_ms, 1)])
        print(f"live 2 tracers (1.0, 1/1.7): {scheme:16} idle {idle:5.1f} %  median frame {frame_ms:6.1f} ms", flush=True)
    write_csv(os.path.join(a.out, "balance_live.csv"), ["scheme", "idle_pct", "median_frame_ms"], rows)


if __name__ == "__main__":
    main()
