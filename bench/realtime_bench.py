#!/usr/bin/env python3
"""Real-time loop benchmark (issue: real-time loop and the game client).

1. hold: builtin:default at a target frame rate with two tracers while capacity changes
   (tracer b leaves, comes back, comes back again with --slowdown 2); frames per second in
   1-second windows from the coordinator's stats (wall_ms), with the quality the workload
   scaler chose. Writes realtime_hold.csv (per frame), realtime_hold_summary.csv (per phase)
   and realtime_hold.png.
2. latency: a headless client in the same run turns the camera and presses the action key;
   its input-to-frame latency and frame intervals (p50/p99) against the bound
   2 x frame interval + render time. Writes realtime_latency.csv.
3. converge: builtin:cornell and builtin:default, a still camera, 1 spp per frame, frames
   dumped by the coordinator with and without converging; RMSE of frame k against a 1024-spp
   pathfarm-render reference, and the single-frame RMS error over sqrt(k) that a running mean
   should follow. Writes realtime_converge.csv and realtime_converge.png.
"""
import argparse
import csv
import os
import statistics
import subprocess
import tempfile
import time

from bench_common import ROOT, rmse, start, wait_for, write_csv
from bench_common import run as run_tool


def tracer(build, port, name, log, extra=()):
    return start([f"{build}/tracer-node/pathfarm-tracer", "--coordinator", f"127.0.0.1:{port}", "--name", name,
                  "--threads", "1", "--max-reconnects", "0", *extra], log)


def read_stats(path):
    with open(path) as f:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]


def hold(a, work):
    os.environ["PATHFARM_SECRET"] = "realtime-bench"
    log = os.path.join(work, "coordinator.log")
    stats = os.path.join(work, "stats.csv")
    seconds = a.phase * 4
    coordinator = start([f"{a.build}/coordinator/pathfarm-coordinator", "--scene", "builtin:default", "--tracer-port",
                         "0", "--client-port", "0", "--width", str(a.width), "--height", str(a.height), "--spp",
                         str(a.spp), "--target-fps", str(a.fps), "--fps", str(a.fps), "--min-tracers", "2",
                         "--stats-csv", stats], log)
    m = wait_for(log, r"tracer_port=(\d+) client_port=(\d+)", "realtime_bench")
    port, client_port = m.group(1), m.group(2)
    client_log = os.path.join(work, "client.log")
    client = start([f"{a.build}/client/pathfarm-client", "--connect", f"127.0.0.1:{client_port}", "--headless",
                    "--turn-rate", "0.2", "--action-every-second", "--latency-csv",
                    os.path.join(work, "latency.csv")], client_log)
    wait_for(log, '"headless-client" connected', "realtime_bench")
    ta = tracer(a.build, port, "a", os.path.join(work, "a.log"))
    tb = tracer(a.build, port, "b", os.path.join(work, "b.log"))
    wait_for(stats, r"\n0,", "realtime_bench")
    t0 = time.time()
    events = []

    def at(t, what, action):
        time.sleep(max(0.0, t0 + t - time.time()))
        events.append((round(time.time() - t0, 2), what))
        return action()

    at(a.phase, "b leaves", lambda: tb.kill())
    tb = at(2 * a.phase, "b back", lambda: tracer(a.build, port, "b", os.path.join(work, "b2.log")))
    at(3 * a.phase, "b restarts --slowdown 2", lambda: tb.kill())
    tb = tracer(a.build, port, "b", os.path.join(work, "b3.log"), ["--slowdown", "2"])
    time.sleep(max(0.0, t0 + seconds - time.time()))
    coordinator.terminate()
    coordinator.wait(timeout=60)
    client.wait(timeout=30)
    for p in (ta, tb):
        p.kill()
    rows = read_stats(stats)
    # Wall time of the first frame is t0 (we started the clock when it appeared).
    base = rows[0]["wall_ms"] / 1000.0
    for r in rows:
        r["t"] = r["wall_ms"] / 1000.0 - base
    return rows, events, open(client_log).read()


def windows(rows, start, end):
    """Frames per second in whole 1-second windows of [start, end)."""
    out = []
    t = start
    while t + 1.0 <= end:
        out.append(sum(1 for r in rows if t <= r["t"] < t + 1.0))
        t += 1.0
    return out


def converge(a, work, scene):
    os.environ["PATHFARM_SECRET"] = "realtime-bench"
    w, h, frames = 160, 90, a.converge_frames
    ref = os.path.join(work, "reference.pfm")
    run_tool([f"{a.build}/tools/pathfarm-render", "--scene", scene, "--width", str(w), "--height",
              str(h), "--spp", str(a.reference_spp), "--frame", "1000000", "--out", ref, "--log-level", "error"],
             "realtime_bench")
    curves = {}
    # Converging alone: the denoiser (docs/denoise.md, bench/denoise_bench.py) is measured apart.
    for variant, extra in (("converge", ["--denoise", "off"]),
                           ("no_converge", ["--no-converge", "--denoise", "off"])):
        dump = os.path.join(work, f"dump_{variant}")
        log = os.path.join(work, f"{variant}.log")
        c = start([f"{a.build}/coordinator/pathfarm-coordinator", "--scene", scene, "--tracer-port", "0",
                   "--width", str(w), "--height", str(h), "--spp", "1", "--fixed-spp", "--game", "free-camera",
                   "--frames", str(frames), "--dump-frames", dump, *extra], log)
        port = wait_for(log, r"tracer_port=(\d+)", "realtime_bench").group(1)
        t = [tracer(a.build, port, n, os.path.join(work, f"{variant}_{n}.log")) for n in ("a", "b")]
        c.wait(timeout=600)
        for p in t:
            p.kill()
        curves[variant] = [rmse(os.path.join(dump, f"frame_{k:06d}.pfm"), ref) for k in range(frames)]
    return curves


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--width", type=int, default=320)
    p.add_argument("--height", type=int, default=180)
    p.add_argument("--spp", type=int, default=4)
    p.add_argument("--fps", type=float, default=10.0, help="target frame rate")
    p.add_argument("--phase", type=float, default=10.0, help="seconds between capacity changes")
    p.add_argument("--converge-frames", type=int, default=64)
    p.add_argument("--reference-spp", type=int, default=1024)
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    work = tempfile.mkdtemp(prefix="realtime_bench_")

    rows, events, client_out = hold(a, work)
    for prev, r in zip(rows, rows[1:]):
        r["interval_ms"] = 1000.0 * (r["t"] - prev["t"])
    rows[0]["interval_ms"] = 0.0
    cols = ["frame", "t", "frame_ms", "tracers", "spp", "rr_scale", "render_width", "render_height", "f", "kept",
            "at_floor", "interval_ms"]
    write_csv(os.path.join(a.out, "realtime_hold.csv"), cols, [[r[c] for c in cols] for r in rows])
    phases = [("2 tracers", 0.0), ("b left", a.phase), ("b back", 2 * a.phase), ("b with --slowdown 2", 3 * a.phase)]
    settle = 2.0  # seconds after each change not counted: the scaler's reaction time
    summary = []
    for i, (name, s) in enumerate(phases):
        e = phases[i + 1][1] if i + 1 < len(phases) else 4 * a.phase
        fps = windows(rows, s + settle, e)
        inside = [r for r in rows if s + settle <= r["t"] < e]
        within = sum(1 for f in fps if abs(f - a.fps) <= 0.1 * a.fps)
        summary.append([name, a.fps, statistics.median(fps) if fps else 0, min(fps, default=0),
                        max(fps, default=0), f"{within}/{len(fps)}",
                        round(statistics.mean(r["spp"] for r in inside), 2) if inside else "",
                        round(statistics.mean(r["render_width"] for r in inside), 1) if inside else "",
                        round(statistics.median(r["frame_ms"] for r in inside), 1) if inside else "",
                        int(max((r["at_floor"] for r in inside), default=0))])
    header = ["phase", "target_fps", "median_fps", "min_fps", "max_fps", "windows_within_10pct", "mean_spp",
              "mean_render_width", "median_frame_ms", "hit_floor"]
    write_csv(os.path.join(a.out, "realtime_hold_summary.csv"), header, summary)
    print(",".join(header))
    for s in summary:
        print(",".join(map(str, s)))
    print("events:", events)

    kv = dict(tok.split("=", 1) for tok in client_out.split() if "=" in tok)
    frame_ms = statistics.median(r["frame_ms"] for r in rows)
    interval = float(kv.get("interval_p50_ms", 0))
    bound = 2 * interval + frame_ms
    lat = [["inputs", kv.get("inputs")], ["latency_p50_ms", kv.get("latency_p50_ms")],
           ["latency_p99_ms", kv.get("latency_p99_ms")], ["interval_p50_ms", kv.get("interval_p50_ms")],
           ["interval_p99_ms", kv.get("interval_p99_ms")], ["median_frame_render_ms", round(frame_ms, 1)],
           ["bound_2_intervals_plus_render_ms", round(bound, 1)],
           ["p50_within_bound", float(kv.get("latency_p50_ms", 1e9)) <= bound]]
    write_csv(os.path.join(a.out, "realtime_latency.csv"), ["metric", "value"], lat)
    for k, v in lat:
        print(f"{k}={v}")

    conv = []
    for scene in ("builtin:cornell", "builtin:default"):
        curves = converge(a, work, scene)
        # Expected for a running mean: the single-frame RMS error (over all frames) / sqrt(k).
        single = (sum(e * e for e in curves["no_converge"]) / len(curves["no_converge"])) ** 0.5
        for k in range(len(curves["converge"])):
            conv.append([scene, k + 1, curves["converge"][k], curves["no_converge"][k],
                         single / (k + 1) ** 0.5])
        for k in (1, 4, 16, 64):
            if k <= len(curves["converge"]):
                print(f"{scene} k={k}: rmse converging={curves['converge'][k - 1]:.4f}, "
                      f"no converging={curves['no_converge'][k - 1]:.4f}, "
                      f"single-frame rms/sqrt(k)={single / k ** 0.5:.4f}")
    write_csv(os.path.join(a.out, "realtime_converge.csv"),
              ["scene", "k", "rmse_converge", "rmse_no_converge", "single_frame_rms_over_sqrt_k"], conv)
    for scene in ("builtin:cornell", "builtin:default"):
        write_csv(os.path.join(work, f"{scene[8:]}.csv"), ["k", "c", "n", "s"], [r[1:] for r in conv if r[0] == scene])

    marks = "\n".join(f"set arrow from {t},graph 0 to {t},graph 1 nohead dt 2 lc rgb 'gray'" for t, _ in events)
    subprocess.run(["gnuplot"], input=f"""
set datafile separator ','
set terminal pngcairo size 1000,560
set output '{a.out}/realtime_hold.png'
set title 'Workload scaling, builtin:default {a.width}x{a.height}, target {a.fps:g} fps (dashed: capacity changes)'
set xlabel 'seconds'
set ylabel 'frame interval, ms'
set y2label 'spp, roulette scale, render width / 100'
set y2tics
set yrange [0:{3 * 1000 / a.fps:g}]
set y2range [0:{max(a.spp, 4) + 1}]
{marks}
plot '{a.out}/realtime_hold.csv' every ::2 using 2:12 title 'frame interval ms' with lines lc rgb 'black', \\
     '' using 2:3 title 'frame render ms' with lines lc rgb '#999999', \\
     '' using 2:5 axes x1y2 title 'spp' with steps lw 2, \\
     '' using 2:6 axes x1y2 title 'roulette scale' with steps lw 2, \\
     '' using 2:($7/100) axes x1y2 title 'render width/100' with steps lw 2, \\
     {1000 / a.fps:g} title 'target interval' lc rgb 'red'
set output '{a.out}/realtime_converge.png'
set title 'Still camera, 160x90, 1 spp per frame: RMSE against a {a.reference_spp}-spp reference'
set logscale xy
set xlabel 'frame k'
set ylabel 'RMSE'
unset y2label
unset y2tics
unset arrow
set yrange [*:*]
plot '{work}/cornell.csv' every ::1 using 1:2 title 'cornell, converging' with linespoints lc 1, \\
     '' every ::1 using 1:3 title 'cornell, no converging' with lines lc 1 dt 3, \\
     '' every ::1 using 1:4 title 'cornell, single-frame RMS/sqrt(k)' with lines lc 1 dt 2, \\
     '{work}/default.csv' every ::1 using 1:2 title 'default, converging' with linespoints lc 2, \\
     '' every ::1 using 1:3 title 'default, no converging' with lines lc 2 dt 3, \\
     '' every ::1 using 1:4 title 'default, single-frame RMS/sqrt(k)' with lines lc 2 dt 2
""", text=True, check=True)


if __name__ == "__main__":
    main()
