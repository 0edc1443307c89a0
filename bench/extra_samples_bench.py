#!/usr/bin/env python3
"""Where extra samples go (coordinator/pacing/extra_samples.h): workload scaling gives a frame a
budget between one spp and the next when the tracers would idle; this bench asks whether
spending it where history is short ("targeted", as the farm does) beats spreading it evenly
("dither") at the same budget, and what each budget buys over 1 spp.

pathfarm-denoise-bench runs each of its three paths (builtin:default's game, a Sponza walk, the
walking Cesium Man; 121 frames at 320x180, 1 spp a frame plus the budget, against the cached
512-spp references of bench/cache/denoise) once per budget and placement. The targeted plan
reads the denoiser's history two frames back, as the farm's does. Same budget means the same
number of samples, so the same render time: the comparison is at equal cost.

Writes bench/results/extra_samples.csv (path means of relative MSE for the raw frames,
converging and the denoiser, and the denoiser's SSIM) and extra_samples.png.
"""
import argparse
import csv
import io
import os
import statistics
import subprocess
import tempfile

from bench_common import ROOT, SCENES, write_csv

PATHS = ["game", "sponza", "cesium"]
BUDGETS = [0.0, 0.125, 0.25, 0.5]
HEADER = ["path", "extra", "placement", "raw_relmse", "converging_relmse", "denoised_relmse",
          "denoised_ssim"]


def run(a, path, extra, placement, strips):
    cmd = [f"{a.build}/bench/pathfarm-denoise-bench", path, SCENES, a.cache, strips, "121", "512",
           "60", "1", "5", "8", "0.3", str(extra), placement]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    rows = list(csv.DictReader(io.StringIO(out)))
    mean = {m: statistics.mean(float(r["relmse"]) for r in rows if r["method"] == m)
            for m in ("raw", "converging", "denoised")}
    ssim = statistics.mean(float(r["ssim"]) for r in rows if r["method"] == "denoised")
    return [path, extra, placement, f"{mean['raw']:.5g}", f"{mean['converging']:.5g}",
            f"{mean['denoised']:.5g}", f"{ssim:.4f}"]


def plot(rows_csv, png):
    script = f"""
set datafile separator ','
set terminal pngcairo size 1200,420
set output '{png}'
set multiplot layout 1,3 title 'Denoised relative MSE against extra samples per pixel (1 spp + budget, 320x180)'
set xlabel 'extra samples per pixel'
set ylabel 'relative MSE (denoised)'
set grid
set key top right
"""
    for path in PATHS:
        script += f"set title '{path}'\nplot "
        script += ", ".join(
            f"'< grep \"^{path},.*,{p},\" {rows_csv}' using 2:6 with linespoints title '{p}'"
            for p in ("targeted", "dither"))
        script += "\n"
    script += "unset multiplot\n"
    subprocess.run(["gnuplot"], input=script, text=True, check=True)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    p.add_argument("--cache", default=os.path.join(ROOT, "bench", "cache", "denoise"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    a = p.parse_args()
    os.makedirs(a.cache, exist_ok=True)
    os.makedirs(a.out, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as strips:
        for path in PATHS:
            for extra in BUDGETS:
                if extra == 0.0:  # nothing to place: one run stands for both lines
                    rows.append(run(a, path, extra, "targeted", strips))
                    rows.append([path, extra, "dither"] + rows[-1][3:])
                else:
                    for placement in ("targeted", "dither"):
                        rows.append(run(a, path, extra, placement, strips))
                print(",".join(str(v) for v in rows[-1]), flush=True)
    rows_csv = os.path.join(a.out, "extra_samples.csv")
    write_csv(rows_csv, HEADER, rows)
    plot(rows_csv, os.path.join(a.out, "extra_samples.png"))


if __name__ == "__main__":
    main()
