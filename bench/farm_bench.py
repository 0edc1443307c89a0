#!/usr/bin/env python3
"""Farm benchmark (issue: the farm): the same frames of builtin:default rendered by a farm of
2 tracers x 1 thread, by 1 tracer x 2 threads and by pathfarm-render with 2 threads, in
alternating rounds; frames/s as medians and ratios to pathfarm-render (the farm's in steady
state, frames 1.. as pathfarm-render times only its render; ratio_with_start counts the tracers'
start and frame 0 as well), the coordinator's
per-stage times, bytes per frame on the wire, and the error figure: farm frames against
pathfarm-render's (RMSE; the determinism contract makes it 0). CSV and a PNG under
bench/results."""
import argparse
import csv
import os
import re
import statistics
import subprocess
import tempfile

from bench_common import ROOT, rmse, start, wait_for, write_csv, batch_mode
from bench_common import run as run_tool


def farm(build, work, tracers, threads, a):
    env = dict(os.environ, PATHFARM_SECRET="farm-bench")
    os.environ.update(env)
    log = os.path.join(work, "coordinator.log")
    coordinator = start([f"{build}/coordinator/pathfarm-coordinator", "--scene", "builtin:default", "--tracer-port", "0",
                         "--client-port", "0", "--width", str(a.width), "--height", str(a.height), "--spp", str(a.spp),
                         "--frames", str(a.frames), "--min-tracers", str(tracers), "--stats-csv", f"{work}/stats.csv",
                         "--stages-csv", f"{work}/stages.csv", "--dump-frames", f"{work}/dump",
                         *batch_mode(f"{build}/coordinator/pathfarm-coordinator")], log)
    port = wait_for(log, r"tracer_port=(\d+)", "farm_bench").group(1)
    procs = [start([f"{build}/tracer-node/pathfarm-tracer", "--coordinator", f"127.0.0.1:{port}", "--threads",
                    str(threads), "--name", f"t{i}", "--max-reconnects", "0"], os.path.join(work, f"t{i}.log"))
             for i in range(tracers)]
    coordinator.wait(timeout=600)
    for p in procs:
        p.wait(timeout=30)
    fps = float(wait_for(log, r"fps=([0-9.]+)", "farm_bench").group(1))
    stats = list(csv.DictReader(open(f"{work}/stats.csv")))
    # Steady state: frames 1.. over the wall time from frame 0's display to the last's. Frame 0
    # and the time before it hold the tracers' start, handshake, snapshot and first build, which
    # pathfarm-render's seconds= leaves out too (it times the render, not loading and building).
    steady = (len(stats) - 1) / ((float(stats[-1]["wall_ms"]) - float(stats[0]["wall_ms"])) / 1000)
    stages = list(csv.DictReader(open(f"{work}/stages.csv")))
    for r in stages:  # builds before the display thread wrote assemble_and_stream_ms
        r.setdefault("assemble_ms", r.get("assemble_and_stream_ms", "0"))
    later = stats[1:]  # frame 0 carries the snapshot
    wire = statistics.mean(int(r["commit_bytes"]) + int(r["tile_bytes"]) for r in later)
    stage_ms = {k: statistics.median(float(r[k]) for r in stages[1:])
                for k in ("send_ms", "prepare_next_ms", "wait_tiles_ms", "assemble_ms")}
    return fps, steady, wire, stage_ms, statistics.median(float(r["idle_pct"]) for r in later)


def render(build, work, a):
    total = 0.0
    for f in range(a.frames):
        out = run_tool([f"{build}/tools/pathfarm-render", "--scene", "builtin:default", "--width", str(a.width),
                        "--height", str(a.height), "--spp", str(a.spp), "--frame", str(f), "--threads", "2",
                        "--out", f"{work}/render_{f}.pfm", "--log-level", "error"], "farm_bench", with_stderr=False)
        total += float(re.search(r"seconds=([0-9.]+)", out).group(1))
    return a.frames / total


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--width", type=int, default=320)
    p.add_argument("--height", type=int, default=180)
    p.add_argument("--spp", type=int, default=4)
    p.add_argument("--frames", type=int, default=30)
    p.add_argument("--rounds", type=int, default=3)
    a = p.parse_args()
    if a.frames < 3:
        raise SystemExit(f"farm_bench: --frames {a.frames}: need at least 3 (frame 0 carries the snapshot)")
    checked = min(5, a.frames - 1)  # the frame compared with pathfarm-render
    os.makedirs(a.out, exist_ok=True)
    runs = []
    for r in range(a.rounds):  # alternate the three set-ups so machine noise hits all alike
        for name, tracers, threads in (("farm_2x1", 2, 1), ("farm_1x2", 1, 2), ("render_2threads", 0, 2)):
            with tempfile.TemporaryDirectory() as work:
                if tracers == 0:
                    fps = render(a.build, work, a)
                    runs.append([r, name, fps, fps, "", "", "", "", "", "", ""])
                    continue
                fps, steady, wire, st, idle = farm(a.build, work, tracers, threads, a)
                if r == 0 and name == "farm_2x1":
                    render_ref = os.path.join(work, "ref.pfm")
                    run_tool([f"{a.build}/tools/pathfarm-render", "--scene", "builtin:default", "--width", str(a.width),
                              "--height", str(a.height), "--spp", str(a.spp), "--frame", str(checked), "--out", render_ref,
                              "--log-level", "error"], "farm_bench")
                    error = rmse(os.path.join(work, "dump", f"frame_{checked:06d}.pfm"), render_ref)
                runs.append([r, name, round(steady, 3), fps, round(wire), st["send_ms"], st["prepare_next_ms"], st["wait_tiles_ms"],
                             st["assemble_ms"], idle, ""])
    header = ["round", "setup", "frames_per_s", "frames_per_s_with_start", "wire_bytes_per_frame", "send_ms", "prepare_next_ms",
              "wait_tiles_ms", "assemble_ms", "idle_pct", "note"]
    write_csv(os.path.join(a.out, "farm_runs.csv"), header, runs)
    setups = ("farm_2x1", "farm_1x2", "render_2threads")
    med = {n: statistics.median(r[2] for r in runs if r[1] == n) for n in setups}
    with_start = {n: statistics.median(r[3] for r in runs if r[1] == n) for n in setups}
    summary = [[n, round(v, 3), round(v / med["render_2threads"], 3),
                round(with_start[n] / with_start["render_2threads"], 3)] for n, v in med.items()]
    write_csv(os.path.join(a.out, "farm.csv"),
              ["setup", "median_frames_per_s", "ratio_to_render", "ratio_with_start"], summary)
    print(",".join(header))
    for r in runs:
        print(",".join(map(str, r)))
    print("setup,median_frames_per_s,ratio_to_render,ratio_with_start")
    for s in summary:
        print(",".join(map(str, s)))
    print(f"rmse_farm_frame{checked}_vs_render={error:.3g}")
    subprocess.run(["gnuplot"], input=f"""
set datafile separator ','
set terminal pngcairo size 800,500
set output '{a.out}/farm.png'
set title 'Frames/s, builtin:default {a.width}x{a.height} {a.spp} spp (median of {a.rounds} alternated rounds)'
set style data histograms
set style fill solid 0.8
set ylabel 'frames per second'
set yrange [0:*]
plot '{a.out}/farm.csv' using 2:xtic(1) notitle
""", text=True, check=True)


if __name__ == "__main__":
    main()
