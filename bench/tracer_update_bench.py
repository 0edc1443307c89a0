#!/usr/bin/env python3
"""The tracer's per-frame scene update against a full rebuild (pathfarm-tracer-update-bench):
a camera walking through Sponza, builtin:default's rolling ball and swinging door, BoxAnimated
and the skinned Cesium Man, on two Embree threads. Writes bench/results/tracer_update.csv and
a log-scale bar chart tracer_update.png. Both columns are measured in one run, alternated per
frame; the images they give are the same bits (tests/render/incremental_update_test.cpp)."""
import argparse
import csv
import io
import os
import subprocess

from bench_common import ROOT, SCENES, run


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--frames", type=int, default=40)
    a = p.parse_args()
    text = run([f"{a.build}/bench/pathfarm-tracer-update-bench", SCENES, str(a.frames)], "tracer_update_bench",
               with_stderr=False)
    rows = list(csv.reader(io.StringIO(text)))
    os.makedirs(a.out, exist_ok=True)
    path = os.path.join(a.out, "tracer_update.csv")
    with open(path, "w", newline="") as f:
        csv.writer(f).writerows(rows)
    for r in rows:
        print(",".join(r))
    subprocess.run(["gnuplot"], input=f"""
set datafile separator ','
set terminal pngcairo size 900,480
set output '{a.out}/tracer_update.png'
set title 'tracer scene update per frame (Embree, 2 threads; medians of {a.frames - 1} frames)'
set style data histograms
set style fill solid 0.8 border -1
set logscale y
set ylabel 'milliseconds'
set grid y
set key top right
set yrange [0.0005:200]
set xtics rotate by -20
plot '{path}' every ::1 using 6:xtic(1) title 'full rebuild (before)', '' every ::1 using 4 title 'update by change set'
""", text=True, check=True)


if __name__ == "__main__":
    main()
