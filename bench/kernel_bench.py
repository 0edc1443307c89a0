#!/usr/bin/env python3
"""Specialised vs generic path-tracing loop (issue: fast and accurate, "skip what a scene
doesn't need"). The two give the same image bit for bit (tests/render/determinism_test.cpp),
so equal error holds by construction and the comparison is cost alone: instructions counted
by valgrind --tool=callgrind (repeatable on a noisy machine) for one single-threaded render
per scene and loop, plus wall time as the median of alternated rounds.
Writes bench/results/kernel_specialisation.csv.
"""
import argparse
import os
import re
import statistics
import subprocess
import tempfile

from bench_common import ROOT, SCENES, write_csv
from bench_common import run as run_tool

SCENE_LIST = [
    ("cornell", "builtin:cornell"),          # emitters only
    ("many-lights", "builtin:many-lights"),  # emitters only
    ("glass", "builtin:glass"),              # emitters, transmission
    ("textured", "{scenes}/flight-helmet/FlightHelmet.gltf"),  # sun/sky (+ transmission?)
    ("default", "builtin:default"),          # everything: the same loop either way
]


def instructions(render, scene, kernel, work):
    out = os.path.join(work, "callgrind.out")
    subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", render, "--scene", scene,
                    "--width", "48", "--height", "27", "--spp", "4", "--threads", "1", "--kernel", kernel,
                    "--out", os.path.join(work, "k.pfm"), "--log-level", "error"],
                   check=True, capture_output=True)
    summary = [l for l in open(out) if l.startswith("summary:") or l.startswith("totals:")][0]
    return int(summary.split()[1])


def seconds(render, scene, kernel, work):
    out = run_tool([render, "--scene", scene, "--width", "160", "--height", "90", "--spp", "16", "--kernel",
                    kernel, "--out", os.path.join(work, "k.pfm"), "--log-level", "error"], "kernel_bench")
    return float(re.search(r"seconds=([0-9.]+)", out).group(1))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--render", default=os.path.join(ROOT, "build", "release", "tools", "pathfarm-render"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--rounds", type=int, default=5)
    a = p.parse_args()
    work = tempfile.mkdtemp(prefix="kernel_bench_")
    rows = []
    for name, spec in SCENE_LIST:
        scene = spec.format(scenes=SCENES)
        ir_generic = instructions(a.render, scene, "generic", work)
        ir_special = instructions(a.render, scene, "specialised", work)
        t = {"generic": [], "specialised": []}
        for _ in range(a.rounds):  # alternated, so drift on the machine hits both alike
            for k in ("generic", "specialised"):
                t[k].append(seconds(a.render, scene, k, work))
        tg, ts = statistics.median(t["generic"]), statistics.median(t["specialised"])
        rows.append([name, ir_generic, ir_special, round(ir_special / ir_generic, 4), tg, ts, round(ts / tg, 3)])
        print(",".join(map(str, rows[-1])), flush=True)
    write_csv(os.path.join(a.out, "kernel_specialisation.csv"),
              ["scene", "instructions_generic", "instructions_specialised", "instruction_ratio",
               "median_s_generic", "median_s_specialised", "time_ratio"], rows)


if __name__ == "__main__":
    main()
