"""Helpers shared by the benchmark scripts: running a tool and writing CSV."""
import csv
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = os.environ.get("PATHFARM_SCENES", os.path.join(ROOT, "..", "shared", "scenes"))


def run(cmd, who, with_stderr=True):
    """Runs cmd; exits with its stderr tail when it fails. Returns stdout (+ stderr)."""
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"{who}: {' '.join(cmd)} failed:\n{out.stderr[-2000:]}")
    return out.stdout + (out.stderr if with_stderr else "")


def start(cmd, log):
    """Starts cmd in the background with stdout and stderr in the file at log."""
    return subprocess.Popen(cmd, stdout=open(log, "w"), stderr=subprocess.STDOUT)


_BATCH = {}


def batch_mode(coordinator):
    """The coordinator arguments of the batch contract (docs/determinism.md): every frame at
    --spp and full size, its own samples, no game logic, no denoiser (for builds that have
    one: benchmarks also run older builds)."""
    if coordinator not in _BATCH:
        has_denoise = "--denoise" in subprocess.run([coordinator, "--help"], capture_output=True, text=True).stdout
        _BATCH[coordinator] = ["--fixed-spp", "--no-converge", "--game", "free-camera"] + (
            ["--denoise", "off"] if has_denoise else [])
    return list(_BATCH[coordinator])


def quantile(values, q):
    """The q-quantile of `values` (nearest rank below); 0 for none."""
    s = sorted(values)
    return s[min(len(s) - 1, int(q * len(s)))] if s else 0.0


def write_csv(path, header, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)


def wait_for(path, pattern, who, timeout=60):
    """The first match of pattern in the file at path, polled until it appears or timeout."""
    end = time.time() + timeout
    while time.time() < end:
        if os.path.exists(path):
            m = re.search(pattern, open(path).read())
            if m:
                return m
        time.sleep(0.05)
    raise SystemExit(f"{who}: {pattern} never appeared in {path}")


def pfm_floats(path):
    """The raw float samples of a PFM written by pathfarm (header: three lines)."""
    data = open(path, "rb").read()
    header_end = 0
    for _ in range(3):
        header_end = data.index(b"\n", header_end) + 1
    return memoryview(data[header_end:]).cast("f")


def rmse(a, b):
    """Root-mean-square difference of two PFM images of the same size."""
    x, y = pfm_floats(a), pfm_floats(b)
    return (sum((p - q) ** 2 for p, q in zip(x, y)) / len(x)) ** 0.5


def errors(image, ref):
    """(RMSE, relative MSE) of a PFM image against a reference: relative MSE is the mean of
    (x - ref)^2 / (ref^2 + 1e-2), the headline metric of the time-vs-error benchmarks."""
    x, r = pfm_floats(image), pfm_floats(ref)
    se = rel = 0.0
    for p, q in zip(x, r):
        d = p - q
        se += d * d
        rel += d * d / (q * q + 1e-2)
    return (se / len(x)) ** 0.5, rel / len(x)
