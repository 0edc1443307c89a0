#!/usr/bin/env python3
"""Render benchmark (issue: foundation): samples/s and rays/s of pathfarm-render at 640x360
beside Embree's own `pathtracer` tutorial on the same OBJ scenes and views, alternated A/B in
one run and summarised as medians and ratios; and, paired with error, the time pathfarm needs
to reach RMSE 0.02 against a converged reference of builtin:cornell, per direct-light
estimator (MIS, light sampling only, BSDF sampling only). Writes CSV files and gnuplot PNGs."""
import argparse
import math
import os
import re
import statistics
import subprocess
import sys

from bench_common import ROOT, SCENES, write_csv
from bench_common import run as run_tool


def run(cmd):
    return run_tool(cmd, "render_bench")


# name, file, look-from, look-at, vertical fov (degrees)
VIEWS = [
    ("cornell-obj", "cornell-box/CornellBox-Original.obj", (0, 1, 3.5), (0, 1, 0), 40),
    ("sponza", "dabrovic-sponza/sponza.obj", (-10, 2, 0), (10, 6, 0), 60),
    ("conference", "conference/conference.obj.gz", (1500, 500, 500), (0, 100, -500), 60),
]
WIDTH, HEIGHT, MAX_DEPTH = 640, 360, 8


def pathfarm(render, scene, extra):
    text = run([render, "--scene", scene, "--log-level", "error", "--max-depth", str(MAX_DEPTH)] + extra)
    summary = [line for line in text.splitlines() if line.startswith("seconds=")][-1]
    fields = dict(re.findall(r"(\w+)=([0-9.eE+-]+)", summary))
    return {k: float(v) for k, v in fields.items()}


def plain_obj(path, cache_dir):
    """Embree's tutorial reads no gzip: unpack into the cache, with the .mtl files beside it."""
    if not path.endswith(".gz"):
        return path
    import glob
    import gzip
    import shutil
    os.makedirs(cache_dir, exist_ok=True)
    target = os.path.join(cache_dir, os.path.basename(path)[:-3])
    if not os.path.exists(target):
        with gzip.open(path, "rb") as src, open(target, "wb") as dst:
            shutil.copyfileobj(src, dst)
    for mtl in glob.glob(os.path.join(os.path.dirname(path), "*.mtl")):
        link = os.path.join(cache_dir, os.path.basename(mtl))
        if not os.path.exists(link):
            os.symlink(os.path.abspath(mtl), link)
    return target


def embree(path, view, frames):
    _, rel, eye, at, fov = view
    path = plain_obj(path, os.path.join(ROOT, "bench", "cache"))
    cmd = ["pathtracer", "-i", path, "--size", str(WIDTH), str(HEIGHT), "--spp", "1",
           "--max-path-length", str(MAX_DEPTH), "--benchmark", "1", str(frames), "--threads", "2",
           "--vp", *map(str, eye), "--vi", *map(str, at), "--vu", "0", "1", "0", "--fov", str(fov),
           "--ambientlight", "0.5", "0.5", "0.5", "--directionallight", "-0.35", "-0.8", "-0.45", "3", "3", "3"]
    text = run(cmd)
    fps = float(re.search(r"BENCHMARK_RENDER_AVG ([0-9.]+)", text).group(1))
    mrays = float(re.search(r"BENCHMARK_RENDER_MRAYPS_AVG ([0-9.]+)", text).group(1))
    return {"samples_per_s": fps * WIDTH * HEIGHT, "rays_per_s": mrays * 1e6}


def throughput(render, rounds, spp, frames, out_dir, baseline=None):
    """With `baseline` (another pathfarm-render), it runs in turn with the two others every
    round, and the summary gains its rays/s and the ratio of ours to it."""
    rows, summary = [], []
    for view in VIEWS:
        name, rel, eye, at, fov = view
        path = os.path.join(SCENES, rel)
        if not os.path.exists(path):
            sys.exit(f"render_bench: {path} missing (set PATHFARM_SCENES)")
        ours, theirs, base = [], [], []
        args = ["--spp", str(spp), "--width", str(WIDTH), "--height", str(HEIGHT),
                "--look-from", *map(str, eye), "--look-at", *map(str, at), "--fov", str(fov)]
        runs = [("pathfarm", ours, lambda: pathfarm(render, path, args + ["--out", os.path.join(out_dir, f"{name}.exr")])),
                ("embree-pathtracer", theirs, lambda: embree(path, view, frames))]
        if baseline:
            runs.append(("pathfarm-baseline", base, lambda: pathfarm(
                baseline, path, args + ["--out", os.path.join(out_dir, f"{name}-baseline.exr")])))
        for r in range(rounds):
            # Alternated so machine noise hits all alike, and the order turned each round: in a
            # fixed order the later runs of a round were measured up to 10 % slower (2026-12-06:
            # a baseline rendering the very same image came out 0.91x).
            for k in range(len(runs)):
                label, results, run = runs[(k + r) % len(runs)]
                x = run()
                results.append(x)
                rows.append([name, label, r, round(x["samples_per_s"]), round(x["rays_per_s"])])
        med = lambda xs, k: statistics.median(x[k] for x in xs)
        line = [name, round(med(ours, "samples_per_s")), round(med(theirs, "samples_per_s")),
                round(med(ours, "samples_per_s") / med(theirs, "samples_per_s"), 3),
                round(med(ours, "rays_per_s")), round(med(theirs, "rays_per_s")),
                round(med(ours, "rays_per_s") / med(theirs, "rays_per_s"), 3)]
        if baseline:
            line += [round(med(base, "rays_per_s")), round(med(ours, "rays_per_s") / med(base, "rays_per_s"), 3)]
        summary.append(line)
    o = [pathfarm(render, "builtin:cornell", ["--spp", str(spp), "--width", str(WIDTH), "--height", str(HEIGHT),
                                              "--out", os.path.join(out_dir, "builtin-cornell.exr")]) for _ in range(rounds)]
    summary.append(["builtin:cornell", round(statistics.median(x["samples_per_s"] for x in o)), "", "",
                    round(statistics.median(x["rays_per_s"] for x in o)), "", ""] + (["", ""] if baseline else []))
    write_csv(os.path.join(out_dir, "throughput_runs.csv"), ["scene", "renderer", "round", "samples_per_s", "rays_per_s"], rows)
    write_csv(os.path.join(out_dir, "throughput.csv"),
              ["scene", "pathfarm_samples_per_s", "embree_samples_per_s", "samples_ratio",
               "pathfarm_rays_per_s", "embree_rays_per_s", "rays_ratio"]
              + (["baseline_rays_per_s", "rays_over_baseline"] if baseline else []), summary)
    return summary


def time_to_error(render, ref_spp, max_log2, out_dir, cache_dir, size=256, target=0.02):
    os.makedirs(cache_dir, exist_ok=True)
    ref = os.path.join(cache_dir, f"cornell_ref_{size}_{ref_spp}.exr")
    if not os.path.exists(ref):
        print(f"render_bench: converged reference {ref} ({ref_spp} spp)...", flush=True)
        pathfarm(render, "builtin:cornell", ["--spp", str(ref_spp), "--width", str(size), "--height", str(size),
                                             "--seed", "987654", "--out", ref])
    rows, reached = [], []
    for variant in ("mis", "light", "bsdf"):
        prev = None
        for k in range(max_log2 + 1):
            spp = 2 ** k
            r = pathfarm(render, "builtin:cornell", ["--spp", str(spp), "--width", str(size), "--height", str(size),
                                                     "--strategy", variant, "--reference", ref,
                                                     "--out", os.path.join(out_dir, "ttr.exr")])
            eff = 1.0 / (r["rel_mse"] * r["seconds"]) if r["rel_mse"] > 0 else float("inf")
            rows.append(["builtin:cornell", variant, spp, r["seconds"], r["rmse"], r["rel_mse"], eff])
            if prev and prev[1] > target >= r["rmse"]:  # log-log interpolation of the crossing
                t = math.exp(math.log(prev[0]) + (math.log(target) - math.log(prev[1])) /
                             (math.log(r["rmse"]) - math.log(prev[1])) * (math.log(r["seconds"]) - math.log(prev[0])))
                reached.append([variant, round(t, 4), spp])
            prev = (r["seconds"], r["rmse"])
    write_csv(os.path.join(out_dir, "time_vs_error.csv"),
              ["scene", "variant", "spp", "seconds", "rmse", "rel_mse", "efficiency"], rows)
    write_csv(os.path.join(out_dir, "time_to_rmse.csv"), ["variant", "seconds_to_rmse_0.02", "spp_reached"], reached)
    return reached


def plot(out_dir):
    script = f"""
set datafile separator ','
set terminal pngcairo size 900,600
set output '{out_dir}/time_vs_error.png'
set title 'builtin:cornell 256x256: RMSE against a converged reference'
set logscale xy
set xlabel 'render seconds'
set ylabel 'RMSE'
set grid
set key top right
plot for [v in "mis light bsdf"] '< grep ",'.v.'," {out_dir}/time_vs_error.csv' using 4:5 with linespoints title v, \\
     0.02 with lines dashtype 2 title 'RMSE 0.02'
set output '{out_dir}/throughput.png'
unset logscale
set title 'Samples/s at 640x360, median of rounds (pathfarm vs Embree pathtracer tutorial)'
set style data histograms
set style histogram clustered
set style fill solid 0.8
set ylabel 'samples per second'
set xlabel ''
plot '< head -4 {out_dir}/throughput.csv' using 2:xtic(1) title 'pathfarm', '' using 3 title 'Embree pathtracer'
"""
    subprocess.run(["gnuplot"], input=script, text=True, check=True)


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--render", default=os.path.join(ROOT, "build", "release", "tools", "pathfarm-render"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--quick", action="store_true", help="fewer rounds and a cheaper reference")
    p.add_argument("--baseline", help="another pathfarm-render, run in turn with the two others")
    p.add_argument("--rounds", type=int, help="rounds of the throughput runs (default 3, 1 with --quick)")
    p.add_argument("--throughput-only", action="store_true", help="skip the time-to-error runs and plots")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    rounds, spp, frames = (1, 4, 4) if a.quick else (3, 16, 16)
    summary = throughput(a.render, a.rounds or rounds, spp, frames, a.out, a.baseline)
    print("scene,pathfarm_samples_per_s,embree_samples_per_s,samples_ratio,pathfarm_rays_per_s,embree_rays_per_s,rays_ratio"
          + (",baseline_rays_per_s,rays_over_baseline" if a.baseline else ""))
    for row in summary:
        print(",".join(map(str, row)))
    if a.throughput_only:
        return
    reached = time_to_error(a.render, 256 if a.quick else 4096, 7 if a.quick else 10, a.out,
                            os.path.join(ROOT, "bench", "cache"))
    plot(a.out)
    print("variant,seconds_to_rmse_0.02,spp_reached")
    for row in reached:
        print(",".join(map(str, row)))


if __name__ == "__main__":
    main()
