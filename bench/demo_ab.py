#!/usr/bin/env python3
"""The demo as a user runs it (scripts/demo.sh: builtin:default's game at a held 10 frames/s,
two 1-thread tracers, a headless client turning), two builds (or one build with two sets of
coordinator or tracer arguments: --args-a/--args-b, --tracer-args-a/--tracer-args-b, or demo
settings: --env-a/--env-b)
alternated round by round: the frame rate, what workload scaling chose (render size, spp,
roulette), each tracer's share of the wall time spent rendering and updating its scene, the
client's input latency, and the display stage's denoiser time (median, p95) and whole time
(p95). Medians over rounds; CSV and a gnuplot PNG under bench/results (issue: tracer speed,
item 5)."""
import argparse
import csv
import os
import re
import statistics
import subprocess
import sys

from bench_common import ROOT, quantile, write_csv


def demo(bin_dir, out_dir, frames, coordinator_args="", tracer_args="", demo_env=()):
    env = dict(os.environ, BIN=bin_dir, OUT=out_dir, FRAMES=str(frames),
               COORDINATOR_ARGS=coordinator_args, TRACER_ARGS=tracer_args)
    env.update(kv.split("=", 1) for kv in demo_env)
    text = subprocess.run(["bash", os.path.join(ROOT, "scripts", "demo.sh")], env=env,
                          capture_output=True, text=True)
    if text.returncode != 0:
        sys.exit(f"demo_ab: the demo with {bin_dir} failed:\n{text.stdout[-1500:]}{text.stderr[-1500:]}")
    coordinator = open(os.path.join(out_dir, "coordinator.log")).read()
    client = open(os.path.join(out_dir, "client.log")).read()
    seconds = float(re.search(r"seconds=([0-9.]+) fps", coordinator).group(1))
    fps = float(re.search(r"frames=\d+ seconds=[0-9.]+ fps=([0-9.]+)", coordinator).group(1))
    latency = {k: float(v) for k, v in re.findall(r"(latency_p\d+_ms)=([0-9.]+)", client)}
    stats = list(csv.DictReader(open(os.path.join(out_dir, "stats.csv"))))
    pixels = statistics.mean(float(r["render_width"]) * float(r["render_height"]) for r in stats)
    spp = statistics.mean(float(r["spp"]) for r in stats)
    rr = statistics.mean(float(r["rr_scale"]) for r in stats)
    # What the tracers send per rendered pixel (colour and first hits, compressed).
    tile_bpp = statistics.mean(float(r["tile_bytes"]) / (float(r["render_width"]) * float(r["render_height"]))
                               for r in stats)
    # The denoiser's time on the display thread, while the tracers render the next frame.
    denoise = [float(r["denoise_ms"]) for r in stats if float(r.get("denoise_ms") or 0.0) > 0.0]
    # The tail after the first 5 frames (the first ones fault every buffer in).
    display = [float(r["display_ms"]) for r in stats[5:]]
    busy, update = {}, {}
    for r in csv.DictReader(open(os.path.join(out_dir, "tracers.csv"))):
        busy[r["tracer"]] = busy.get(r["tracer"], 0.0) + float(r["render_ms"])
        update[r["tracer"]] = update.get(r["tracer"], 0.0) + float(r.get("update_ms") or 0.0)
    render_pct = statistics.mean(100.0 * ms / 1000.0 / seconds for ms in busy.values())
    update_pct = statistics.mean(100.0 * ms / 1000.0 / seconds for ms in update.values())
    return {"fps": fps, "pixels": pixels, "spp": spp, "rr_scale": rr, "render_pct": render_pct,
            "update_pct": update_pct, "latency_p50_ms": latency.get("latency_p50_ms", 0.0),
            "latency_p99_ms": latency.get("latency_p99_ms", 0.0),
            "denoise_ms_p50": statistics.median(denoise) if denoise else 0.0,
            "denoise_ms_p95": quantile(denoise[5:], 0.95),
            "display_ms_p95": quantile(display, 0.95),
            "tile_bytes_per_px": tile_bpp}


KEYS = ["fps", "pixels", "spp", "rr_scale", "render_pct", "update_pct", "latency_p50_ms",
        "latency_p99_ms", "denoise_ms_p50", "tile_bytes_per_px", "denoise_ms_p95",
        "display_ms_p95"]


def plot(out, rounds):
    script = f"""
set datafile separator ','
set terminal pngcairo size 1000,500
set output '{out}/demo_ab.png'
set title 'The demo (builtin:default, 10 frames/s, 2 tracers x 1 thread): medians of {rounds} rounds'
set style data histograms
set style histogram clustered
set style fill solid 0.8
set key outside right
set yrange [0:*]
set ylabel 'percent of wall time / ms / thousand pixels'
plot '{out}/demo_ab.csv' skip 1 using 6:xtic(1) title 'tracer rendering %', '' skip 1 using 7 title 'tracer updating %', \\
     '' skip 1 using 8 title 'latency p50 ms', '' skip 1 using ($3/1000) title 'render pixels / 1000', \\
     '' skip 1 using 12 title 'denoise p95 ms', '' skip 1 using 13 title 'display stage p95 ms'
"""
    subprocess.run(["gnuplot"], input=script, text=True, check=True)


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--a", required=True, help="build tree A (the baseline)")
    p.add_argument("--b", default=os.path.join(ROOT, "build", "release"), help="build tree B")
    p.add_argument("--args-a", default="", help="more coordinator arguments for A")
    p.add_argument("--args-b", default="", help="more coordinator arguments for B (the same "
                   "tree twice with different arguments compares options)")
    p.add_argument("--tracer-args-a", default="", help="more tracer arguments for A")
    p.add_argument("--tracer-args-b", default="", help="more tracer arguments for B")
    p.add_argument("--env-a", action="append", default=[], metavar="KEY=VALUE",
                   help="a setting of scripts/demo.sh for A (e.g. TRACER_NICE=0); repeatable")
    p.add_argument("--env-b", action="append", default=[], metavar="KEY=VALUE",
                   help="a setting of scripts/demo.sh for B")
    p.add_argument("--label-a", default="before")
    p.add_argument("--label-b", default="after")
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--frames", type=int, default=100)
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--plot-only", action="store_true", help="redraw the PNG from the CSV")
    a = p.parse_args()
    if a.plot_only:
        return plot(a.out, a.rounds)
    os.makedirs(a.out, exist_ok=True)
    work = os.path.join(ROOT, "bench", "cache", "demo_ab")
    rows, runs = [], {a.label_a: [], a.label_b: []}
    for r in range(a.rounds):  # alternated so machine noise hits both alike
        for label, tree, args, tracer_args, env in (
                (a.label_a, a.a, a.args_a, a.tracer_args_a, a.env_a),
                (a.label_b, a.b, a.args_b, a.tracer_args_b, a.env_b)):
            m = demo(tree, os.path.join(work, f"{label}_{r}"), a.frames, args, tracer_args, env)
            runs[label].append(m)
            rows.append([label, r] + [round(m[k], 3) for k in KEYS])
            print(label, r, " ".join(f"{k}={m[k]:.2f}" for k in KEYS), flush=True)
    write_csv(os.path.join(a.out, "demo_ab_runs.csv"), ["build", "round"] + KEYS, rows)
    summary = [[label] + [round(statistics.median(m[k] for m in ms), 3) for k in KEYS]
               for label, ms in runs.items()]
    write_csv(os.path.join(a.out, "demo_ab.csv"), ["build"] + KEYS, summary)
    plot(a.out, a.rounds)
    print(",".join(["build"] + KEYS))
    for row in summary:
        print(",".join(map(str, row)))


if __name__ == "__main__":
    main()
