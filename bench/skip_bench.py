#!/usr/bin/env python3
"""What each "skip what a scene doesn't need" saves, at equal error, side by side.

- Light culling (emitters a closed surface separates from the camera are not sampled), on
  builtin:sealed-lights: culled vs --no-light-culling at equal spp. The two estimators differ
  in noise, so the figure is efficiency = 1 / (relMSE x seconds): its ratio is how much less time
  culling needs for the same error.
- The path-tracing loop specialised for the scene's features vs the generic loop, on scenes that
  lack features (no sun/sky, no glass, no emitters), for the Embree and the OpenCL backends. Both
  loops give the same image (tested), so the time ratio at equal spp is the ratio at equal error.

Every pair is measured A/B alternating, `--repeats` times after a warm-up; medians. Writes
bench/results/skips.csv and skips.png.
"""
import argparse
import os
import re
import statistics
import subprocess
import tempfile

from bench_common import ROOT, SCENES, write_csv
from bench_common import errors as errors_of
from bench_common import run as run_tool

# (skip, scene name, scene, backend, variant A args, variant B args, spp)
PAIRS = [
    ("light-culling", "sealed-lights", "builtin:sealed-lights", "embree", [], ["--no-light-culling"], 16),
    ("light-culling", "sealed-lights", "builtin:sealed-lights", "opencl", [], ["--no-light-culling"], 16),
]
SPECIALISATION_SCENES = [
    ("cornell", "builtin:cornell"),            # emitters only
    ("many-lights", "builtin:many-lights"),    # emitters only
    ("textured", "{scenes}/flight-helmet/FlightHelmet.gltf"),  # sun/sky only
    ("sponza", "{scenes}/dabrovic-sponza/sponza.obj"),        # sun/sky only
]
for _name, _scene in SPECIALISATION_SCENES:
    for _backend in ("embree", "opencl"):
        PAIRS.append(("specialised-loop", _name, _scene, _backend, ["--kernel", "specialised"],
                      ["--kernel", "generic"], 16))


def render(a, scene, backend, spp, extra, out):
    cmd = [a.render, "--scene", scene, "--width", str(a.width), "--height", str(a.height), "--spp", str(spp),
           "--backend", backend, "--threads", "2", "--out", out, "--log-level", "error", *extra]
    line = [l for l in run_tool(cmd, "skip_bench").splitlines() if "seconds=" in l][-1]
    return {k: float(v) for k, v in re.findall(r"(\w+)=([0-9.eE+-]+)", line)}




def plot(a, csv_path):
    subprocess.run(["gnuplot"], input=f"""
set datafile separator ','
set terminal pngcairo size 1000,600
set output '{a.out}/skips.png'
set title 'Time saved at equal error by each skip: efficiency 1/(relMSE x s) with / without ({a.width}x{a.height})'
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set logscale y
set yrange [0.5:10]
set ylabel 'efficiency with / without'
set xtics rotate by -35 scale 0
set bmargin 12
set rmargin 12
set grid y
plot '{csv_path}' using 11:xtic(stringcolumn(1).': '.stringcolumn(2).' '.stringcolumn(3)) notitle lc rgb '#3070b0', \\
     1 with lines notitle lc rgb 'gray'
""", text=True, check=True)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--render", default=os.path.join(ROOT, "build", "release", "tools", "pathfarm-render"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--cache", default=os.path.join(ROOT, "bench", "cache"))
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--plot-only", action="store_true", help="redraw skips.png from skips.csv")
    a = p.parse_args()
    a.width, a.height = 320, 180
    if a.plot_only:
        return plot(a, os.path.join(a.out, "skips.csv"))
    os.environ.setdefault("POCL_CACHE_DIR", os.path.join(a.cache, "pocl"))
    work = tempfile.mkdtemp(prefix="skip_bench_")
    rows = []
    for skip, name, spec, backend, args_a, args_b, spp in PAIRS:
        scene = spec.format(scenes=SCENES)
        ref = os.path.join(a.cache, f"tve_{name}_{a.width}x{a.height}_2048.pfm")
        if not os.path.exists(ref):
            print(f"skip_bench: making the 2048-spp reference of {name}", flush=True)
            render(a, scene, "embree", 2048, ["--seed", "987654"], ref)
        for extra in (args_a, args_b):  # warm-up (PoCL kernel cache, first Embree build)
            render(a, scene, backend, 1, extra, os.path.join(work, "warm.pfm"))
        seconds = {"a": [], "b": []}
        errors = {}
        for _ in range(a.repeats):
            for key, extra in (("a", args_a), ("b", args_b)):
                image = os.path.join(work, f"{key}.pfm")
                seconds[key].append(render(a, scene, backend, spp, extra, image)["seconds"])
                errors[key] = errors_of(image, ref)[1]
        t = {k: statistics.median(v) for k, v in seconds.items()}
        eff = {k: 1.0 / (errors[k] * t[k]) for k in t}
        row = [skip, name, backend, " ".join(args_a) or "default", " ".join(args_b), spp,
               f"{t['a']:.4f}", f"{t['b']:.4f}", f"{errors['a']:.5g}", f"{errors['b']:.5g}",
               f"{eff['a'] / eff['b']:.3f}"]
        rows.append(row)
        print(",".join(map(str, row)), flush=True)
    header = ["skip", "scene", "backend", "with", "without", "spp", "seconds_with", "seconds_without",
              "rel_mse_with", "rel_mse_without", "efficiency_gain"]
    csv_path = os.path.join(a.out, "skips.csv")
    write_csv(csv_path, header, rows)
    plot(a, csv_path)


if __name__ == "__main__":
    main()
