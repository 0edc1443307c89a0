#!/usr/bin/env python3
"""Many-light sampling (issue: light tree): time to a relative MSE of 1e-2 and 1e-3, the light
tree against choosing emitters by power, and the tree with resampled selection (RIS, 2 and 4
candidates) against the tree alone, alternated in one run.

Scenes: builtin:many-lights (2 048 emissive triangles on a ceiling) and builtin:light-field
(9 892 small emitters of six colours over the ceiling and upper walls, 2 000 on a turning ring). For each, pathfarm-render renders at
doubling spp with each sampler in turn (A, B, C, D, A, B ... at each spp, --rounds times; the median
seconds of a point is kept) against a cached 4096-spp reference, and the time at which each
sampler's relative MSE crosses a target comes from log-log interpolation (time_vs_error.py's).

Writes bench/results/light_tree_bench.csv (every point), light_tree_time_to_error.csv (per
scene and target: seconds for each sampler and their ratio) and light_tree_bench.png.

--all-scenes: every scene of bench/time_vs_error.py and builtin:furnace at equal spp, samplers
alternated, median seconds: the tree's and auto's (the default, which chooses between tree and
power per scene) time at equal error relative to power's, (t_tree rel_tree) / (t_power
rel_power) since the error falls as 1/time; light_tree_scenes.csv. The issue allows 1.03.
"""
import argparse
import os
import statistics
import subprocess

from bench_common import ROOT, write_csv
from time_vs_error import FULL_SCENES, crossing, render  # render: pathfarm-render's figures
from bench_common import SCENES as SCENE_DIR

SCENES = [("many-lights", "builtin:many-lights"), ("light-field", "builtin:light-field")]
# The samplers compared: emitters by power, the tree, and the tree with resampled selection
# (RIS) over 2 and 4 candidates per light sample (--light-candidates).
SAMPLER_ARGS = {
    "power": ["--light-sampler", "power"],
    "tree": ["--light-sampler", "tree"],
    "tree+ris2": ["--light-sampler", "tree", "--light-candidates", "2"],
    "tree+ris4": ["--light-sampler", "tree", "--light-candidates", "4"],
}
SAMPLERS = list(SAMPLER_ARGS)
TARGETS = [1e-2, 1e-3]


def reference(a, name, scene):
    os.makedirs(a.cache, exist_ok=True)
    path = os.path.join(a.cache, f"ref_{name}_{a.width}x{a.height}.pfm")
    if not os.path.exists(path):
        print(f"light_tree_bench: reference {name} ({a.ref_spp} spp, tree)...", flush=True)
        render(a, scene, ["--spp", str(a.ref_spp), "--seed", "424242", "--light-sampler", "tree",
                          "--out", path])
    return path


def measure(a, name, scene, ref):
    """Rows (scene, sampler, spp, seconds, rel_mse, efficiency) for every spp and sampler."""
    rows = []
    for spp in a.spp:
        seconds = {s: [] for s in SAMPLERS}
        rel = {}
        for _ in range(a.rounds):
            for s in SAMPLERS:  # alternated: A B A B
                r = render(a, scene, ["--spp", str(spp), "--seed", "5", *SAMPLER_ARGS[s],
                                      "--reference", ref, "--out", os.path.join(a.work, "o.pfm")])
                seconds[s].append(r["seconds"])
                rel[s] = r["rel_mse"]  # same seed: the same image every round
        for s in SAMPLERS:
            t = statistics.median(seconds[s])
            rows.append([name, s, spp, round(t, 4), rel[s], round(1.0 / (rel[s] * t), 3)])
            print(",".join(map(str, rows[-1])), flush=True)
    return rows


def plot(a, rows_csv, png):
    subprocess.run(["gnuplot"], input=f"""
set datafile separator ','
set terminal pngcairo size 1100,480
set output '{png}'
set multiplot layout 1,2 title 'Light selection: power, tree, tree + RIS ({a.width}x{a.height}, relative MSE against {a.ref_spp} spp)'
set logscale xy
set xlabel 'render seconds'
set ylabel 'relative MSE'
set grid
set key bottom left
do for [sc in "{' '.join(n for n, _ in SCENES)}"] {{
  set title sc
  plot for [s in "{' '.join(SAMPLERS)}"] \\
       '< grep "^'.sc.','.s.'," {rows_csv}' using 4:5 with linespoints title s, \\
       1e-2 with lines dt 2 lc rgb 'gray' title '1e-2', 1e-3 with lines dt 3 lc rgb 'gray' title '1e-3'
}}
unset multiplot
""", text=True, check=True)


# Beside time_vs_error.py's scenes: the one where the tree cannot pay for itself (an emitting
# sphere round a ball: every element gives every point of the sphere the same light per area).
EXTRA_SCENES = [("furnace", "builtin:furnace")]


def all_scenes(a):
    rows = []
    samplers = ("power", "tree", "auto")
    for name, spec in FULL_SCENES + EXTRA_SCENES:
        scene = spec.format(scenes=SCENE_DIR)
        ref = os.path.join(a.cache, f"check_{name}_{a.width}x{a.height}.pfm")
        if not os.path.exists(ref):
            print(f"light_tree_bench: reference {name} (1024 spp)...", flush=True)
            render(a, scene, ["--spp", "1024", "--seed", "987654", "--out", ref])
        seconds = {s: [] for s in samplers}
        rel = {}
        for round_ in range(a.rounds):
            for k in range(len(samplers)):  # alternated, the order turned each round
                s = samplers[(k + round_) % len(samplers)]
                r = render(a, scene, ["--spp", "16", "--seed", "5", "--light-sampler", s,
                                      "--reference", ref, "--out", os.path.join(a.work, "o.pfm")])
                seconds[s].append(r["seconds"])
                rel[s] = r["rel_mse"]
        t = {s: statistics.median(seconds[s]) for s in seconds}
        ratio = {s: (t[s] * rel[s]) / (t["power"] * rel["power"]) for s in ("tree", "auto")}
        rows.append([name, round(t["power"], 4), rel["power"], round(t["tree"], 4), rel["tree"],
                     round(ratio["tree"], 3), round(t["auto"], 4), rel["auto"],
                     round(ratio["auto"], 3)])
        print(",".join(map(str, rows[-1])), flush=True)
    write_csv(os.path.join(a.out, "light_tree_scenes.csv"),
              ["scene", "power_seconds", "power_rel_mse", "tree_seconds", "tree_rel_mse",
               "tree_time_at_equal_error", "auto_seconds", "auto_rel_mse",
               "auto_time_at_equal_error"], rows)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default=os.path.join(ROOT, "build", "ci"))
    p.add_argument("--width", type=int, default=160)
    p.add_argument("--height", type=int, default=90)
    p.add_argument("--ref-spp", type=int, default=4096)
    p.add_argument("--spp", type=int, nargs="+", default=[1, 2, 4, 8, 16, 32, 64, 128, 256])
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--cache", default=os.path.join(ROOT, "bench", "cache", "light_tree"))
    p.add_argument("--all-scenes", action="store_true")
    a = p.parse_args()
    a.render = os.path.join(a.build, "tools", "pathfarm-render")
    a.work = os.path.join(a.cache, "work")
    os.makedirs(a.work, exist_ok=True)
    os.makedirs(a.out, exist_ok=True)
    if a.all_scenes:
        return all_scenes(a)
    rows = []
    for name, scene in SCENES:
        rows += measure(a, name, scene, reference(a, name, scene))
    rows_csv = os.path.join(a.out, "light_tree_bench.csv")
    write_csv(rows_csv, ["scene", "sampler", "spp", "seconds", "rel_mse", "efficiency"], rows)
    summary = []
    for name, _ in SCENES:
        for target in TARGETS:
            t = {s: crossing([(r[3], r[4]) for r in rows if r[0] == name and r[1] == s], target)
                 for s in SAMPLERS}
            def ratio(x, y):
                return round(t[x] / t[y], 3) if t[x] and t[y] else ""
            summary.append([name, target] + [t[s] or "never" for s in SAMPLERS] +
                           [ratio("tree", "power"), ratio("tree+ris2", "tree"), ratio("tree+ris4", "tree")])
            print(f"{name}: relMSE {target:g}: " + ", ".join(f"{s} {t[s]} s" for s in SAMPLERS) +
                  f"; tree/power {ratio('tree', 'power')}", flush=True)
    write_csv(os.path.join(a.out, "light_tree_time_to_error.csv"),
              ["scene", "target_rel_mse"] + [f"{s}_seconds" for s in SAMPLERS] +
              ["tree_over_power", "ris2_over_tree", "ris4_over_tree"], summary)
    plot(a, rows_csv, os.path.join(a.out, "light_tree_bench.png"))


if __name__ == "__main__":
    main()
