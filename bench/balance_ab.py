#!/usr/bin/env python3
"""Live balancing, A/B: two tracers of unequal speed (one --slowdown 1.7, optionally both with
--hiccup-p), the farm's schemes run alternately for several rounds on one scene, in real time
(builtin:default's game at a held frame rate, as the demo runs) or in batch (--fixed-spp).
Per run: mean idle % (the farm's stats), median and p95 frame time; per scheme: the median over
rounds. Writes bench/results/balance_ab_<name>.csv (every run) and prints the summary.

Machines here are noisy: only the alternated medians are worth comparing."""
import argparse
import csv
import os
import statistics
import tempfile

from bench_common import ROOT, SCENES, start, wait_for, write_csv, batch_mode

TRACES = os.path.join(ROOT, "tools", "balance-sim", "traces")


def coordinator_args(a, scheme, stats, tracer_stats):
    args = ["--scene", a.scene, "--tracer-port", "0", "--client-port", "0", "--width", "320",
            "--height", "180", "--frames", str(a.frames), "--min-tracers", "2", "--balancer", scheme,
            "--stats-csv", stats, "--tracer-stats-csv", tracer_stats]
    if a.realtime:
        return args + ["--spp", "2", "--target-fps", "10"]
    return args + ["--spp", "4"] + batch_mode(f"{a.build}/coordinator/pathfarm-coordinator")


def one_run(a, scheme, work):
    os.environ["PATHFARM_SECRET"] = "balance-ab"
    scheme, _, alpha = scheme.partition("@")  # scheme@a: ours with --speed-smoothing a
    log, stats, tracer_stats = (os.path.join(work, n) for n in ("coordinator.log", "stats.csv", "tracers.csv"))
    smoothing = ["--speed-smoothing", alpha] if alpha else []
    coordinator = start([f"{a.build}/coordinator/pathfarm-coordinator"] + coordinator_args(a, scheme, stats, tracer_stats)
                        + smoothing, log)
    ports = wait_for(log, r"tracer_port=(\d+) client_port=(\d+)", "balance_ab")
    client_args = ["--turn-rate", "0.3"] if a.realtime else ["--script", os.path.join(TRACES, "slow_path.txt")]
    client = start([f"{a.build}/client/pathfarm-client", "--connect", f"127.0.0.1:{ports.group(2)}", "--headless",
                    "--frames", str(a.frames)] + client_args, os.path.join(work, "client.log"))
    wait_for(log, '"headless-client" connected', "balance_ab")
    hiccups = ["--hiccup-p", str(a.hiccup_p)]
    tracers = [start([f"{a.build}/tracer-node/pathfarm-tracer", "--coordinator", f"127.0.0.1:{ports.group(1)}",
                      "--threads", "1", "--name", name, "--max-reconnects", "0"] + hiccups + extra,
                     os.path.join(work, f"{name}.log"))
               for name, extra in (("fast", ["--hiccup-seed", "1"]),
                                   ("slow", ["--slowdown", "1.7", "--hiccup-seed", "2"]))]
    coordinator.wait(timeout=900)
    for p in tracers + [client]:
        p.wait(timeout=60)
    rows = list(csv.DictReader(open(stats)))[a.skip:]
    frame_ms = sorted(float(r["frame_ms"]) for r in rows)
    return {"idle_pct": statistics.mean(float(r["idle_pct"]) for r in rows),
            "median_frame_ms": statistics.median(frame_ms),
            "p95_frame_ms": frame_ms[min(len(frame_ms) - 1, int(0.95 * len(frame_ms)))]}


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--name", default="default_realtime", help="suffix of the CSV")
    p.add_argument("--scene", default="builtin:default")
    p.add_argument("--realtime", action="store_true", help="the real-time loop at 10 frames/s")
    p.add_argument("--schemes", default="perfect-smooth,cost-predictive")
    p.add_argument("--rounds", type=int, default=4)
    p.add_argument("--frames", type=int, default=120)
    p.add_argument("--skip", type=int, default=10, help="first frames left out (warm-up)")
    p.add_argument("--hiccup-p", type=float, default=0.0)
    a = p.parse_args()
    if a.scene.startswith("{scenes}"):
        a.scene = a.scene.format(scenes=SCENES)
    schemes = a.schemes.split(",")
    runs = []
    for r in range(a.rounds):
        for scheme in schemes:
            with tempfile.TemporaryDirectory() as work:
                m = one_run(a, scheme, work)
            runs.append([r, scheme] + [round(m[k], 3) for k in ("idle_pct", "median_frame_ms", "p95_frame_ms")])
            print(f"round {r} {scheme}: idle {m['idle_pct']:.2f} %, median frame {m['median_frame_ms']:.1f} ms, "
                  f"p95 {m['p95_frame_ms']:.1f} ms", flush=True)
    write_csv(os.path.join(a.out, f"balance_ab_{a.name}.csv"),
              ["round", "scheme", "idle_pct", "median_frame_ms", "p95_frame_ms"], runs)
    for scheme in schemes:
        mine = [x for x in runs if x[1] == scheme]
        print(f"{scheme}: median over {len(mine)} rounds: idle {statistics.median(x[2] for x in mine):.2f} %, "
              f"median frame {statistics.median(x[3] for x in mine):.1f} ms, p95 {statistics.median(x[4] for x in mine):.1f} ms")


if __name__ == "__main__":
    main()
