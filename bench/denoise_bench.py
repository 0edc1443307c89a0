#!/usr/bin/env python3
"""Reconstruction quality benchmark (issue: real-time reconstruction).

Three scripted paths of 121 frames at 320x180, 1 spp a frame (the farm's fixed-spp mode, with
converging): builtin:default with its game running (ball, lamp and door switched by the action
key, the camera walking and turning), a walk through Sponza, an orbit around the walking,
skinned Cesium Man. pathfarm-denoise-bench runs the coordinator's frame pipeline and renders
each frame as a tracer does; every 10th frame (and the frame after every 20th) is compared with
a 512-spp reference of the same scene state and camera, cached under bench/cache/denoise.

For raw frames, converging alone and the denoiser: relative MSE, SSIM (tonemapped luma) and
the temporal instability (mean absolute frame-to-frame change of the error, over the
reference's mean). Writes bench/results/denoise_bench.csv (per frame), denoise_summary.csv
(path means and the denoised / converging ratios), denoise_bench.png and image strips
(raw | converging | denoised | reference) under docs/; then the denoiser's cost per frame alone
on 2 threads at 320x180 and 640x360 (3x3 and 5x5 kernels alternated) in denoise_cost.csv. The
cost while tracers run is the farm's `denoise_ms` (scripts/demo.sh's stats.csv).
"""
import argparse
import csv
import os
import shutil
import statistics
import subprocess

from bench_common import ROOT, write_csv

PATHS = ["game", "sponza", "cesium"]
METHODS = ["raw", "converging", "denoised"]


def run_path(a, path, strips):
    cmd = [f"{a.build}/bench/pathfarm-denoise-bench", path, a.scenes, a.cache, strips, str(a.frames),
           str(a.ref_spp), str(a.strip_frame), str(a.radius), str(a.levels), str(a.sigma_l),
           str(a.taa_alpha), "0", "targeted", "weighted", str(a.edge_frames)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return list(csv.DictReader(out.splitlines()))


def summarise(rows):
    summary = []
    for path in PATHS:
        means = {}
        for m in METHODS:
            sel = [r for r in rows if r["path"] == path and r["method"] == m]
            if not sel:
                continue
            unstable = [float(r["instability"]) for r in sel if r["instability"]]
            means[m] = {"relmse": statistics.mean(float(r["relmse"]) for r in sel),
                        "ssim": statistics.mean(float(r["ssim"]) for r in sel),
                        "instability": statistics.mean(unstable) if unstable else float("nan"),
                        "denoise_ms": statistics.median(float(r["denoise_ms"]) for r in sel)}
        for m, v in means.items():
            summary.append([path, m, f"{v['relmse']:.5g}", f"{v['ssim']:.4f}", f"{v['instability']:.4f}",
                            f"{v['denoise_ms']:.2f}",
                            f"{v['relmse'] / means['converging']['relmse']:.3f}" if "converging" in means else ""])
    return summary


def cost(a):
    """The denoiser alone on 2 threads (no tracers running), 3x3 and 5x5 kernels alternated."""
    rows = []
    for rnd in range(a.cost_rounds):
        for radius in (1, 2):
            out = subprocess.run([f"{a.build}/bench/pathfarm-denoise-filter-bench", "builtin:default", "20", "2",
                                  str(radius), "320", "180", "640", "360"], check=True, capture_output=True,
                                 text=True).stdout
            rows += [dict(r, round=rnd) for r in csv.DictReader(out.splitlines())]
    summary = []
    for radius in ("1", "2"):
        for size in (("320", "180"), ("640", "360")):
            for mode in ("temporal", "moving", "single"):
                sel = [float(r["median_ms"]) for r in rows
                       if r["radius"] == radius and (r["width"], r["height"]) == size and r["mode"] == mode]
                summary.append([radius, f"{size[0]}x{size[1]}", mode, f"{statistics.median(sel):.2f}", len(sel)])
    return summary


def plot(out):
    script = f"""
set datafile separator ','
set terminal pngcairo size 1200,400
set output '{out}/denoise_bench.png'
set multiplot layout 1,3 title 'Relative MSE against 512-spp references, 1 spp a frame at 320x180'
set logscale y
set key top right
set xlabel 'frame'
"""
    for path in PATHS:
        script += f"set title '{path}'\nplot "
        script += ", ".join(
            f"'< grep \"^{path},\" {out}/denoise_bench.csv | grep \",{m},\"' using 2:4 with linespoints title '{m}'"
            for m in METHODS) + "\n"
    script += "unset multiplot\n"
    subprocess.run(["gnuplot"], input=script, text=True, check=True)


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    p.add_argument("--scenes", default=os.environ.get("PATHFARM_SCENES", os.path.join(ROOT, "..", "shared", "scenes")))
    p.add_argument("--cache", default=os.path.join(ROOT, "bench", "cache", "denoise"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--docs", default=os.path.join(ROOT, "docs"))
    p.add_argument("--frames", type=int, default=121)
    p.add_argument("--ref-spp", type=int, default=512)
    p.add_argument("--strip-frame", type=int, default=60)
    p.add_argument("--paths", default=",".join(PATHS))
    p.add_argument("--radius", type=int, default=1, help="the wavelet's kernel radius (2: SVGF's 5x5)")
    p.add_argument("--levels", type=int, default=5)
    p.add_argument("--sigma-l", type=float, default=8.0, help="the luminance edge's sigma (SVGF: 4)")
    p.add_argument("--taa-alpha", type=float, default=0.3, help="the temporal anti-aliasing's blend (0: off)")
    p.add_argument("--edge-frames", type=float, default=3.0,
                   help="the far side of silhouettes' weight, in frames of history (0: off)")
    p.add_argument("--tag", default="", help="suffix of the output files (variants side by side)")
    p.add_argument("--cost-rounds", type=int, default=3, help="rounds of the cost measurement (0: none)")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    strips = os.path.join(a.cache, "strips")
    rows = []
    for path in a.paths.split(","):
        rows += run_path(a, path, strips)
        if not a.tag:
            shutil.copy(os.path.join(strips, f"denoise_{path}_strip.png"), os.path.join(a.docs, f"denoise_{path}.png"))
    header = ["path", "frame", "method", "relmse", "ssim", "instability", "denoise_ms"]
    write_csv(os.path.join(a.out, f"denoise_bench{a.tag}.csv"), header, [[r[h] for h in header] for r in rows])
    summary = summarise(rows)
    write_csv(os.path.join(a.out, f"denoise_summary{a.tag}.csv"),
              ["path", "method", "mean_relmse", "mean_ssim", "mean_instability", "median_denoise_ms",
               "relmse_over_converging"], summary)
    for s in summary:
        print(",".join(s))
    if not a.tag:
        plot(a.out)
    if a.cost_rounds > 0:
        costs = cost(a)
        write_csv(os.path.join(a.out, "denoise_cost.csv"), ["radius", "size", "mode", "median_ms", "runs"], costs)
        for c in costs:
            print(",".join(map(str, c)))


if __name__ == "__main__":
    main()
