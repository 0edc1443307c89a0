#!/usr/bin/env python3
"""JPEG q90 against H.264 at equal PSNR, per frame, at 320x180 and 640x360 (issue: the game in
a browser: H.264 at most 5 ms a frame at 320x180 on one thread, at least 3x fewer bytes).

Records the frames a client receives (scripts/demo.sh with --dump-frames: builtin:default's
game, the client turning, workload scaling and the denoiser on; cached in bench/cache/codec),
then runs pathfarm-codec-bench over them: JPEG at several qualities and H.264 at several CRFs,
one thread, with the browsers' stream settings (veryfast, high profile, zerolatency) and the
same tuned for PSNR (x264's psnr tune: no psychovisual optimisation, which spends bits where
PSNR does not see them). The H.264 bytes and time at JPEG q90's PSNR are interpolated between
the two CRFs around it. Writes
bench/results/codec_bench.csv, codec_equal_psnr.csv and codec_bench.png (rate-distortion)."""
import argparse
import csv
import io
import math
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def record(build, size, frames, cache):
    folder = os.path.join(cache, f"{size[0]}x{size[1]}")
    if os.path.isdir(folder) and len(os.listdir(folder)) >= frames:
        return folder
    os.makedirs(folder, exist_ok=True)
    env = dict(os.environ, BIN=build, OUT=os.path.join(cache, "demo"), FRAMES=str(frames),
               WIDTH=str(size[0]), HEIGHT=str(size[1]),
               COORDINATOR_ARGS=f"--dump-frames {folder}")
    subprocess.run([os.path.join(ROOT, "scripts", "demo.sh")], env=env, check=True,
                   stdout=subprocess.DEVNULL)
    return folder


def at_psnr(rows, psnr, field):
    """`field` of the H.264 rows interpolated at `psnr` (bytes log-linearly)."""
    rows = sorted(rows, key=lambda r: r["psnr_mean"])
    for lo, hi in zip(rows, rows[1:]):
        if lo["psnr_mean"] <= psnr <= hi["psnr_mean"]:
            t = (psnr - lo["psnr_mean"]) / (hi["psnr_mean"] - lo["psnr_mean"])
            if field == "bytes_mean":
                return math.exp((1 - t) * math.log(lo[field]) + t * math.log(hi[field]))
            return (1 - t) * lo[field] + t * hi[field]
    raise SystemExit(f"codec_bench: PSNR {psnr:.2f} dB outside the CRFs' range")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    p.add_argument("--frames", type=int, default=60)
    p.add_argument("--cache", default=os.path.join(ROOT, "bench", "cache", "codec"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    table, summary = [], []
    for size in ((320, 180), (640, 360)):
        folder = record(a.build, size, a.frames, a.cache)
        rows = []
        for name, setting, qualities in (("h264", "veryfast:high", "50,70,80,90,95"),
                                         ("h264-psnr", "veryfast:high:psnr,zerolatency", "90")):
            out = subprocess.run([os.path.join(a.build, "bench", "pathfarm-codec-bench"),
                                  folder, setting, "1", qualities, "9,12,15,18,21,24,27,30"],
                                 capture_output=True, text=True, check=True).stdout
            part = [{k: (v if k == "codec" else float(v)) for k, v in r.items()}
                    for r in csv.DictReader(io.StringIO(out))]
            for r in part:
                r["codec"] = name if r["codec"] == "h264" else r["codec"]
            rows += [r for r in part if r["codec"] != "jpeg" or name == "h264"]
        table += rows
        jpeg = next(r for r in rows if r["codec"] == "jpeg" and r["setting"] == 90)
        for name in ("h264", "h264-psnr"):
            h264 = [r for r in rows if r["codec"] == name]
            bytes_h264 = at_psnr(h264, jpeg["psnr_mean"], "bytes_mean")
            ms_h264 = at_psnr(h264, jpeg["psnr_mean"], "encode_ms_median")
            summary.append([f"{size[0]}x{size[1]}", name, round(jpeg["psnr_mean"], 2),
                            round(jpeg["bytes_mean"]), round(jpeg["encode_ms_median"], 3),
                            round(bytes_h264), round(ms_h264, 3),
                            round(jpeg["bytes_mean"] / bytes_h264, 2)])
            print(f"{size[0]}x{size[1]}: JPEG q90 {jpeg['psnr_mean']:.2f} dB, "
                  f"{jpeg['bytes_mean']:.0f} B, {jpeg['encode_ms_median']:.2f} ms; {name} at "
                  f"that PSNR {bytes_h264:.0f} B, {ms_h264:.2f} ms: "
                  f"{jpeg['bytes_mean'] / bytes_h264:.2f}x fewer bytes")
    with open(os.path.join(a.out, "codec_bench.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(table[0].keys()))
        w.writeheader()
        w.writerows(table)
    with open(os.path.join(a.out, "codec_equal_psnr.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["size", "h264", "psnr_db", "jpeg_q90_bytes", "jpeg_q90_ms", "h264_bytes", "h264_ms",
                    "bytes_ratio"])
        w.writerows(summary)
    plot(a.out, table)


def plot(out, table):
    data = os.path.join(out, "codec_bench.dat")
    with open(data, "w") as f:
        for codec in ("jpeg", "h264", "h264-psnr"):
            for size in ((320, 180), (640, 360)):
                f.write(f"# {codec} {size[0]}x{size[1]}\n")
                for r in sorted((r for r in table if r["codec"] == codec and
                                 r["width"] == size[0]), key=lambda r: r["bytes_mean"]):
                    f.write(f"{r['bytes_mean'] / 1024:.3f} {r['psnr_mean']:.3f}\n")
                f.write("\n\n")
    png = os.path.join(out, "codec_bench.png")
    subprocess.run(["gnuplot", "-e", f"""set terminal pngcairo size 720,420; set output '{png}';
        set logscale x; set xlabel 'KiB per frame'; set ylabel 'PSNR (dB) against the frame sent';
        set key bottom right; set grid;
        set title 'JPEG (q 50-95) vs H.264 (CRF 9-30, veryfast, high, 1 thread): demo frames';
        plot '{data}' index 0 with linespoints title 'JPEG 320x180',
             '' index 1 with linespoints title 'JPEG 640x360',
             '' index 2 with linespoints title 'H.264 320x180',
             '' index 3 with linespoints title 'H.264 640x360',
             '' index 4 with linespoints dt 2 title 'H.264 psnr tune 320x180',
             '' index 5 with linespoints dt 2 title 'H.264 psnr tune 640x360'"""], check=True)
    os.remove(data)


if __name__ == "__main__":
    main()
