#!/usr/bin/env python3
"""Time against error, per scene (issue: fast and accurate).

For each benchmark scene it makes (and caches in bench/cache/) a converged reference at a fixed
high spp, renders with increasing samples per pixel (and, in the full run, increasing time
budgets), and records render seconds, RMSE, relative MSE (squared error over the reference's
squared value plus 1e-2) and efficiency = 1 / (relMSE x seconds). Variants side by side in one
run: MIS vs light sampling only vs BSDF sampling only, the loop specialised for the scene's
features vs the generic one ("generic"), the Embree backend vs the OpenCL backend on PoCL
("opencl", MIS), pathfarm-render vs the farm (two 1-thread tracers). Writes bench/results/time_vs_error_scenes.csv, time_to_rel_mse.csv and one
log-log plot per scene (time_vs_error_<scene>.png).

--quick (CI): two small scenes at 96x54, a 256-spp reference, up to 16 spp; fails if MIS's
(or OpenCL's) relative MSE does not fall at least 4x from 1 to 16 spp.
--variants a,b --merge: run only those variants and replace their rows in the existing CSV.
"""
import argparse
import csv
import math
import os
import re
import subprocess
import sys
import tempfile

from bench_common import ROOT, SCENES, errors, start, wait_for, write_csv, batch_mode
from bench_common import run as run_tool

FULL_SCENES = [
    ("cornell", "builtin:cornell"),
    ("default", "builtin:default"),
    ("glass", "builtin:glass"),
    ("textured", "{scenes}/flight-helmet/FlightHelmet.gltf"),
    ("many-lights", "builtin:many-lights"),
    ("sponza", "{scenes}/dabrovic-sponza/sponza.obj"),
    ("sibenik", "{scenes}/sibenik/sibenik.obj"),
    ("conference", "{scenes}/conference/conference.obj.gz"),
]
QUICK_SCENES = [("cornell", "builtin:cornell"), ("glass", "builtin:glass")]
FARM_SCENES = {"cornell", "default", "sponza"}
# Variant -> pathfarm-render arguments. The specialised loop is the default (--kernel).
VARIANTS = {
    "mis": ["--strategy", "mis"],
    "light": ["--strategy", "light"],
    "bsdf": ["--strategy", "bsdf"],
    "generic": ["--strategy", "mis", "--kernel", "generic"],
    "opencl": ["--strategy", "mis", "--backend", "opencl"],
}


def render(a, scene, extra):
    out = run_tool([a.render, "--scene", scene, "--width", str(a.width), "--height", str(a.height),
                    "--log-level", "error", *extra], "time_vs_error")
    line = [l for l in out.splitlines() if "seconds=" in l][-1]
    return {k: float(v) for k, v in re.findall(r"(\w+)=([0-9.eE+-]+)", line)}


def reference(a, name, scene):
    os.makedirs(a.cache, exist_ok=True)
    path = os.path.join(a.cache, f"tve_{name}_{a.width}x{a.height}_{a.ref_spp}.pfm")
    if not os.path.exists(path):
        print(f"time_vs_error: reference {name} ({a.ref_spp} spp)...", flush=True)
        render(a, scene, ["--spp", str(a.ref_spp), "--seed", "987654", "--out", path])
    return path




def farm_point(a, scene, spp, ref, work):
    """The third frame of a 2-tracer farm (the first includes the tracers' scene build):
    (seconds of the frame, rmse, rel_mse)."""
    os.environ["PATHFARM_SECRET"] = "time-vs-error"
    log, stats, dump = (os.path.join(work, n) for n in ("farm.log", "farm_stats.csv", "farm_dump"))
    build = os.path.dirname(os.path.dirname(a.render))
    coordinator = start(
        [f"{build}/coordinator/pathfarm-coordinator", "--scene", scene, "--tracer-port", "0", "--width",
         str(a.width), "--height", str(a.height), "--spp", str(spp), "--frames", "3", "--min-tracers", "2",
         *batch_mode(f"{build}/coordinator/pathfarm-coordinator"), "--stats-csv", stats, "--dump-frames", dump],
        log)
    port = wait_for(log, r"tracer_port=(\d+)", "time_vs_error").group(1)
    tracers = [subprocess.Popen([f"{build}/tracer-node/pathfarm-tracer", "--coordinator", f"127.0.0.1:{port}",
                                 "--threads", "1", "--name", f"t{i}", "--max-reconnects", "0"],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL) for i in range(2)]
    coordinator.wait(timeout=1800)
    for t in tracers:
        t.kill()
    frame_ms = float(open(stats).read().splitlines()[3].split(",")[2])
    rmse, rel = errors(os.path.join(dump, "frame_000002.pfm"), ref)
    return frame_ms / 1000.0, rmse, rel


def crossing(series, target):
    """Seconds at which rel_mse first reaches target, by log-log interpolation; None if never."""
    for (t0, e0), (t1, e1) in zip(series, series[1:]):
        if e0 > target >= e1 and e1 > 0 and t1 > t0:
            return math.exp(math.log(t0) + (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0)) *
                            (math.log(t1) - math.log(t0)))
    if series and series[0][1] <= target:
        return series[0][0]
    return None


def plot(a, scenes, rows):
    """One log-log plot of relative MSE against seconds per scene, every variant."""
    csv_path = os.path.join(a.out, "time_vs_error_scenes.csv")
    for name, _ in scenes:
        variants = " ".join(dict.fromkeys(r[1] for r in rows if r[0] == name))
        subprocess.run(["gnuplot"], input=f"""
set datafile separator ','
set terminal pngcairo size 800,560
set output '{a.out}/time_vs_error_{name}.png'
set title '{name} {a.width}x{a.height}: relative MSE against a {a.ref_spp}-spp reference'
set logscale xy
set xlabel 'render seconds'
set ylabel 'relative MSE'
set grid
set key bottom left
plot for [v in "{variants}"] \\
     '< grep "^{name},'.v.'," {csv_path}' using 4:6 with linespoints title v, \\
     1e-2 with lines dt 2 lc rgb 'gray' title 'relMSE 1e-2', 1e-3 with lines dt 3 lc rgb 'gray' title 'relMSE 1e-3'
""", text=True, check=True)


def farm_only(a, scenes, work):
    path = os.path.join(a.out, "time_vs_error_scenes.csv")
    with open(path) as f:
        rows = [r for r in csv.reader(f)]
    header, rows = rows[0], [r for r in rows[1:] if r[1] != "farm-2x1"]
    for name, spec in scenes:
        if name not in FARM_SCENES:
            continue
        ref = reference(a, name, spec.format(scenes=SCENES))
        for spp in (4, 16):
            seconds, rmse, rel = farm_point(a, spec.format(scenes=SCENES), spp, ref, work)
            rows.append([name, "farm-2x1", spp, seconds, rmse, rel, 1.0 / (rel * seconds)])
            print(",".join(map(str, rows[-1])), flush=True)
    order = [n for n, _ in FULL_SCENES]
    rows.sort(key=lambda r: order.index(r[0]) if r[0] in order else len(order))
    write_csv(path, header, rows)
    plot(a, [s for s in scenes if s[0] in FARM_SCENES], rows)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--render", default=os.path.join(ROOT, "build", "release", "tools", "pathfarm-render"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--cache", default=os.path.join(ROOT, "bench", "cache"))
    p.add_argument("--quick", action="store_true")
    p.add_argument("--scenes", default="", help="comma-separated subset of the scene names")
    p.add_argument("--farm-only", action="store_true",
                   help="recompute only the farm rows of an existing time_vs_error_scenes.csv")
    p.add_argument("--variants", default=",".join(VARIANTS), help="comma-separated subset of: " + ",".join(VARIANTS))
    p.add_argument("--merge", action="store_true",
                   help="replace only the rows of --variants in an existing time_vs_error_scenes.csv")
    a = p.parse_args()
    variants = [v for v in a.variants.split(",") if v]
    if any(v not in VARIANTS for v in variants):
        sys.exit(f"time_vs_error: --variants {a.variants}: unknown variant (known: {','.join(VARIANTS)})")
    os.environ.setdefault("POCL_CACHE_DIR", os.path.join(a.cache, "pocl"))
    a.width, a.height = (96, 54) if a.quick else (320, 180)
    a.ref_spp = 256 if a.quick else 2048
    max_log2 = 4 if a.quick else 8
    scenes = QUICK_SCENES if a.quick else FULL_SCENES
    if a.scenes:
        scenes = [s for s in scenes if s[0] in a.scenes.split(",")]
    os.makedirs(a.out, exist_ok=True)
    work = tempfile.mkdtemp(prefix="time_vs_error_")
    if a.farm_only:
        return farm_only(a, scenes, work)
    rows, reached, failures = [], [], []
    for name, spec in scenes:
        scene = spec.format(scenes=SCENES)
        ref = reference(a, name, scene)
        image = os.path.join(work, "image.pfm")
        series = {}
        if "opencl" in variants:  # PoCL builds the kernels once (cached), before timing
            render(a, scene, ["--spp", "1", "--out", image, *VARIANTS["opencl"]])
        for variant in variants:
            for k in range(max_log2 + 1):
                spp = 2 ** k
                r = render(a, scene, ["--spp", str(spp), "--out", image, *VARIANTS[variant]])
                rmse, rel = errors(image, ref)
                rows.append([name, variant, spp, r["seconds"], rmse, rel, 1.0 / (rel * r["seconds"])])
                series.setdefault(variant, []).append((r["seconds"], rel))
            print(f"{name} {variant}: rel_mse {series[variant][0][1]:.4g} at 1 spp, "
                  f"{series[variant][-1][1]:.4g} at {2 ** max_log2} spp", flush=True)
        if not a.quick and not a.merge:
            for budget in (0.5, 1.0, 2.0, 4.0, 8.0):  # pathfarm-render --seconds: doubling passes
                r = render(a, scene, ["--seconds", str(budget), "--out", image])
                rmse, rel = errors(image, ref)
                rows.append([name, "mis-time-budget", int(r["spp"]), r["seconds"], rmse, rel,
                             1.0 / (rel * r["seconds"])])
            if name in FARM_SCENES:
                for spp in (4, 16):
                    seconds, rmse, rel = farm_point(a, scene, spp, ref, work)
                    rows.append([name, "farm-2x1", spp, seconds, rmse, rel, 1.0 / (rel * seconds)])
        for variant in series:
            for target in (1e-2, 1e-3):
                t = crossing(series[variant], target)
                reached.append([name, variant, target, round(t, 4) if t else f"not reached in {2 ** max_log2} spp"])
        for variant in ("mis", "opencl"):
            if variant in series and series[variant][-1][1] * 4 > series[variant][0][1]:
                failures.append(f"{name}: {variant} rel_mse {series[variant][0][1]:.4g} -> {series[variant][-1][1]:.4g}")
        # Same images (same random numbers), so the time ratio at equal spp is the ratio at equal error.
        for variant, base in (("generic", "mis"), ("opencl", "mis")):
            if variant in series and base in series:
                ratios = [t / b for (t, _), (b, _) in zip(series[variant], series[base])][max_log2 // 2:]
                print(f"{name}: {variant} time / {base} time at equal spp (>= {2 ** (max_log2 // 2)} spp): "
                      f"median {sorted(ratios)[len(ratios) // 2]:.3f}", flush=True)
    header = ["scene", "variant", "spp", "seconds", "rmse", "rel_mse", "efficiency"]
    reached_header = ["scene", "variant", "target_rel_mse", "seconds"]
    csv_path = os.path.join(a.out, "time_vs_error_scenes.csv")
    reached_path = os.path.join(a.out, "time_to_rel_mse.csv")
    if a.merge:  # keep the rows of the variants (and scenes) not re-run
        done = {(r[0], r[1]) for r in rows}
        with open(csv_path) as f:
            old_rows = [r for r in list(csv.reader(f))[1:] if (r[0], r[1]) not in done]
        rows = old_rows + rows
        with open(reached_path) as f:
            old_reached = [r for r in list(csv.reader(f))[1:] if (r[0], r[1]) not in done]
        reached = old_reached + reached
        order = [n for n, _ in FULL_SCENES]
        rows.sort(key=lambda r: order.index(r[0]) if r[0] in order else len(order))
        reached.sort(key=lambda r: order.index(r[0]) if r[0] in order else len(order))
    write_csv(csv_path, header, rows)
    write_csv(reached_path, reached_header, reached)
    print(",".join(reached_header))
    for r in reached:
        print(",".join(map(str, r)))
    plot(a, [s for s in FULL_SCENES if any(r[0] == s[0] for r in rows)] if a.merge else scenes, rows)
    if failures:
        sys.exit("time_vs_error: error does not fall with samples: " + "; ".join(failures))


if __name__ == "__main__":
    main()
