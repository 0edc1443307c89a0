#!/usr/bin/env python3
"""Coordinator-core benchmark: BVH maintenance figures (pathfarm-accel-bench) and commit bytes
per frame for every animated scene in ../shared/scenes (pathfarm-coordinator --offline, 60
frames at 30 fps, replica checked every frame). Writes CSV and PNG plots under bench/results."""
import argparse
import csv
import os
import subprocess

from bench_common import ROOT, SCENES, write_csv
from bench_common import run as run_tool

ANIMATED = ["animated-triangle/AnimatedTriangle.gltf", "animated-cube/AnimatedCube.gltf",
            "box-animated/BoxAnimated.gltf", "interpolation-test/InterpolationTest.gltf",
            "animated-morph-cube/AnimatedMorphCube.gltf", "simple-skin/SimpleSkin.gltf",
            "rigged-simple/RiggedSimple.gltf", "rigged-figure/RiggedFigure.gltf",
            "cesium-man/CesiumMan.gltf", "fox/Fox.glb"]


def run(cmd):
    return run_tool(cmd, "coordinator_bench", with_stderr=False)


def commit_bytes(coordinator, out_dir, frames):
    rows = []
    for rel in ["builtin:default"] + ANIMATED:
        scene = rel if rel.startswith("builtin:") else os.path.join(SCENES, rel)
        stats = os.path.join(out_dir, "offline_stats.csv")
        run([coordinator, "--scene", scene, "--offline", "--frames", str(frames), "--stats-csv", stats,
             "--log-level", "error"])
        with open(stats) as f:
            data = list(csv.DictReader(f))
        later = data[1:]
        per_frame = sum(int(r["commit_bytes"]) for r in later) / len(later)
        rows.append([rel.split("/")[0], int(data[0]["commit_bytes"]), round(per_frame),
                     max(int(r["commit_bytes"]) for r in later),
                     round(sum(float(r["animate_ms"]) for r in later) / len(later), 4),
                     round(sum(float(r["accel_ms"]) for r in later) / len(later), 4),
                     max(int(r["dynamic_tris"]) for r in later),
                     all(r["replica_ok"] == "1" for r in data)])
    header = ["scene", "snapshot_bytes", "mean_commit_bytes_per_frame", "max_commit_bytes",
              "animate_ms", "accel_ms", "dynamic_tris", "replica_ok_all_frames"]
    write_csv(os.path.join(out_dir, "commit_bytes.csv"), header, rows)
    return header, rows


def plot(out_dir):
    script = f"""
set datafile separator ','
set terminal pngcairo size 1000,600
set output '{out_dir}/commit_bytes.png'
set title 'Commit bytes per frame (mean over 60 frames) vs snapshot size'
set style data histograms
set style histogram clustered
set style fill solid 0.8
set logscale y
set ylabel 'bytes'
set xtics rotate by -30
set key outside
plot '{out_dir}/commit_bytes.csv' using 2:xtic(1) title 'snapshot', '' using 3 title 'per frame'
set output '{out_dir}/accel.png'
set title 'BVH maintenance, ms per 1000 triangles or instances (pathfarm; thesis: rebuild 1.02, refit 0.092)'
unset logscale
set ylabel 'ms per 1000'
plot '{out_dir}/accel.csv' using 4:xtic(1) title 'pathfarm'
"""
    subprocess.run(["gnuplot"], input=script, text=True, check=True)


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--frames", type=int, default=60)
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    accel = run([os.path.join(a.build, "bench", "pathfarm-accel-bench"), SCENES])
    with open(os.path.join(a.out, "accel.csv"), "w") as f:
        f.write(accel)
    print(accel, end="")
    header, rows = commit_bytes(os.path.join(a.build, "coordinator", "pathfarm-coordinator"), a.out, a.frames)
    print(",".join(header))
    for r in rows:
        print(",".join(map(str, r)))
    plot(a.out)


if __name__ == "__main__":
    main()
