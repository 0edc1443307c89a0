#!/usr/bin/env python3
"""Per-ray cost by scene (issue: tracer speed, "per-ray cost depends on the scene more than it
should"): rays/s and samples/s of pathfarm-render on scenes of one light and of thousands,
each light sampler in turn every round (order turned each round), medians; every figure is
also given over builtin:cornell's rays/s in the same run.

builtin:furnace (a ball inside a sphere of 5 000 emitting triangles, every surface emitting 0.5
and reflecting half) has an exact answer, 1 - 0.5^(d + 1) at maximum depth d, so its error is
measured against that constant image: the light tree's (and auto's, which chooses per scene)
time at equal error over power's, (t_tree mse_tree) / (t_power mse_power), since the error
falls as 1/time.

Writes bench/results/scene_ray_cost.csv (medians), scene_ray_cost_runs.csv (every run) and
scene_ray_cost.png.
"""
import argparse
import os
import statistics
import struct
import subprocess

from bench_common import ROOT, SCENES, errors, write_csv
from time_vs_error import render  # pathfarm-render's seconds=, rays_per_s= ... figures

CORNELL_OBJ = ["--look-from", "0", "1", "3.5", "--look-at", "0", "1", "0", "--fov", "40"]
# name, scene, extra arguments, samplers
CASES = [
    ("builtin:cornell", "builtin:cornell", [], ["tree"]),
    ("cornell-obj", os.path.join(SCENES, "cornell-box", "CornellBox-Original.obj"), CORNELL_OBJ,
     ["tree"]),
    ("builtin:default", "builtin:default", [], ["tree", "auto"]),
    ("builtin:furnace", "builtin:furnace", [], ["tree", "power", "auto"]),
    ("builtin:light-field", "builtin:light-field", [], ["tree", "power", "auto"]),
]


def constant_pfm(path, width, height, value):
    with open(path, "wb") as f:
        f.write(f"PF\n{width} {height}\n-1.0\n".encode())
        f.write(struct.pack(f"<{width * height * 3}f", *([value] * (width * height * 3))))


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default=os.path.join(ROOT, "build", "ci"))
    p.add_argument("--width", type=int, default=320)
    p.add_argument("--height", type=int, default=180)
    p.add_argument("--spp", type=int, default=16)
    p.add_argument("--max-depth", type=int, default=8)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    a = p.parse_args()
    a.render = os.path.join(a.build, "tools", "pathfarm-render")
    os.makedirs(a.out, exist_ok=True)
    work = os.path.join(ROOT, "bench", "cache", "scene_ray_cost")
    os.makedirs(work, exist_ok=True)
    exact = os.path.join(work, f"furnace_exact_{a.width}x{a.height}_d{a.max_depth}.pfm")
    constant_pfm(exact, a.width, a.height, 1.0 - 0.5 ** (a.max_depth + 1))

    runs, figures = [], {}
    common = ["--spp", str(a.spp), "--max-depth", str(a.max_depth), "--threads", str(a.threads)]
    jobs = [(name, scene, extra, s) for name, scene, extra, samplers in CASES for s in samplers]
    for r in range(a.rounds):
        for k in range(len(jobs)):
            name, scene, extra, sampler = jobs[(k + r) % len(jobs)]
            image = os.path.join(work, "out.pfm")
            x = render(a, scene, common + extra + ["--light-sampler", sampler, "--out", image])
            mse = errors(image, exact)[0] ** 2 if name == "builtin:furnace" else ""
            runs.append([name, sampler, r, x["seconds"], round(x["rays_per_s"]),
                         round(x["samples_per_s"]), mse])
            figures.setdefault((name, sampler), []).append((x, mse))
    write_csv(os.path.join(a.out, "scene_ray_cost_runs.csv"),
              ["scene", "sampler", "round", "seconds", "rays_per_s", "samples_per_s", "mse"], runs)

    med = lambda key, field: statistics.median(x[field] for x, _ in figures[key])
    cornell = med(("builtin:cornell", "tree"), "rays_per_s")
    rows = []
    for name, sampler in figures:
        key = (name, sampler)
        rays, samples = med(key, "rays_per_s"), med(key, "samples_per_s")
        mse = figures[key][0][1]  # same seed every round: the same image
        rows.append([name, sampler, round(med(key, "seconds"), 4), round(rays), round(samples),
                     round(rays / samples, 3), round(rays / cornell, 3),
                     f"{mse:.4g}" if mse != "" else ""])
    header = ["scene", "sampler", "seconds", "rays_per_s", "samples_per_s", "rays_per_sample",
              "rays_per_s_over_builtin_cornell", "mse_against_exact"]
    csv_path = os.path.join(a.out, "scene_ray_cost.csv")
    write_csv(csv_path, header, rows)
    print(",".join(header))
    for row in rows:
        print(",".join(map(str, row)))
    furnace = {s: (med(("builtin:furnace", s), "seconds"), figures[("builtin:furnace", s)][0][1])
               for s in ("tree", "power", "auto")}
    for s in ("tree", "auto"):
        ratio = (furnace[s][0] * furnace[s][1]) / (furnace["power"][0] * furnace["power"][1])
        print(f"builtin:furnace: {s}'s time at equal error over power's = {ratio:.3f}")

    subprocess.run(["gnuplot"], input=f"""
set datafile separator ','
set terminal pngcairo size 900,480
set output '{os.path.join(a.out, "scene_ray_cost.png")}'
set title 'Rays/s by scene and light sampler ({a.width}x{a.height}, {a.spp} spp, {a.threads} threads, medians of {a.rounds})'
set style data histograms
set style fill solid 0.6
set boxwidth 0.8
set ylabel 'million rays/s'
set yrange [0:*]
set xtics rotate by -25
set grid ytics
plot '{csv_path}' every ::1 using ($4/1e6):xticlabels(stringcolumn(1).' '.stringcolumn(2)) notitle
""", text=True, check=True)


if __name__ == "__main__":
    main()
