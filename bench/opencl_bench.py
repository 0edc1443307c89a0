#!/usr/bin/env python3
"""Samples per second of the OpenCL backend (PoCL on this CPU) against the Embree backend, on
the same scenes and machine, at equal error.

Both backends draw the same per-sample random numbers, so at equal samples per pixel their
images are nearly identical and their errors against a converged reference equal: the
samples/s ratio is then the speed ratio at equal RMSE. Each point is measured A/B alternating
(embree, opencl, embree, ...) `--repeats` times after one warm-up of each (PoCL's kernel cache,
Embree's first build); medians are reported with the RMSE and relative MSE of each backend
against the cached 2048-spp references of time_vs_error.py.

Writes bench/results/opencl_vs_embree.csv and opencl_vs_embree.png.
"""
import argparse
import os
import re
import statistics
import subprocess
import tempfile

from bench_common import ROOT, SCENES, errors, write_csv
from bench_common import run as run_tool

BENCH_SCENES = [
    ("cornell", "builtin:cornell"),
    ("default", "builtin:default"),
    ("glass", "builtin:glass"),
    ("textured", "{scenes}/flight-helmet/FlightHelmet.gltf"),
    ("sponza", "{scenes}/dabrovic-sponza/sponza.obj"),
    ("sibenik", "{scenes}/sibenik/sibenik.obj"),
]


def render(a, scene, backend, spp, out):
    cmd = [a.render, "--scene", scene, "--width", str(a.width), "--height", str(a.height),
           "--spp", str(spp), "--backend", backend, "--threads", str(a.threads), "--out", out,
           "--log-level", "error"]
    line = [l for l in run_tool(cmd, "opencl_bench").splitlines() if "seconds=" in l][-1]
    return {k: float(v) for k, v in re.findall(r"(\w+)=([0-9.eE+-]+)", line)}




def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--render", default=os.path.join(ROOT, "build", "release", "tools", "pathfarm-render"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--cache", default=os.path.join(ROOT, "bench", "cache"))
    p.add_argument("--spp", type=int, default=16)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--scenes", default="", help="comma-separated subset of the scene names")
    a = p.parse_args()
    a.width, a.height = 320, 180
    os.environ.setdefault("POCL_CACHE_DIR", os.path.join(a.cache, "pocl"))
    scenes = [s for s in BENCH_SCENES if not a.scenes or s[0] in a.scenes.split(",")]
    work = tempfile.mkdtemp(prefix="opencl_bench_")
    rows = []
    for name, spec in scenes:
        scene = spec.format(scenes=SCENES)
        ref = os.path.join(a.cache, f"tve_{name}_{a.width}x{a.height}_2048.pfm")
        if not os.path.exists(ref):
            print(f"opencl_bench: making the 2048-spp reference of {name}", flush=True)
            render(a, scene, "embree", 2048, ref)
        for backend in ("embree", "opencl"):  # warm-up
            render(a, scene, backend, 1, os.path.join(work, "warm.pfm"))
        seconds = {"embree": [], "opencl": []}
        err = {}
        for _ in range(a.repeats):
            for backend in ("embree", "opencl"):
                image = os.path.join(work, f"{backend}.pfm")
                r = render(a, scene, backend, a.spp, image)
                seconds[backend].append(r["seconds"])
                err[backend] = errors(image, ref)
        samples = a.width * a.height * a.spp
        med = {b: statistics.median(s) for b, s in seconds.items()}
        row = [name, a.spp, f"{samples / med['embree']:.0f}", f"{samples / med['opencl']:.0f}",
               f"{med['opencl'] / med['embree']:.2f}", f"{err['embree'][0]:.5g}", f"{err['opencl'][0]:.5g}",
               f"{err['embree'][1]:.5g}", f"{err['opencl'][1]:.5g}"]
        rows.append(row)
        print(",".join(map(str, row)), flush=True)
    header = ["scene", "spp", "embree_samples_per_s", "opencl_samples_per_s", "opencl_time_over_embree",
              "embree_rmse", "opencl_rmse", "embree_rel_mse", "opencl_rel_mse"]
    csv_path = os.path.join(a.out, "opencl_vs_embree.csv")
    write_csv(csv_path, header, rows)
    subprocess.run(["gnuplot"], input=f"""
set datafile separator ','
set terminal pngcairo size 800,480
set output '{a.out}/opencl_vs_embree.png'
set title 'samples/s at {a.spp} spp, {a.width}x{a.height}, {a.threads} threads (equal RMSE: same random numbers)'
set style data histograms
set style fill solid 0.8 border -1
set logscale y
set ylabel 'samples per second'
set grid y
set key top right
plot '{csv_path}' using 3:xtic(1) title 'Embree', '' using 4 title 'OpenCL (PoCL)'
""", text=True, check=True)


if __name__ == "__main__":
    main()
