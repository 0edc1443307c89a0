#!/usr/bin/env python3
"""JPEG q90 against H.264 at equal PSNR and at equal SSIM, per frame, at 320x180 and 640x360
(issue: the game in a browser: H.264 at most 5 ms a frame at 320x180 on one thread, at least 3x
fewer bytes at equal PSNR).

Records the frames a client receives (scripts/demo.sh with --dump-frames: builtin:default's
game, the client turning, workload scaling and the denoiser on; cached in bench/cache/codec),
then runs pathfarm-codec-bench over them: JPEG at several qualities and H.264 at several CRFs,
one thread, with
- h264: the coordinator's stream settings (h264_stream_settings: faster up to 320x240 with
  every partition size, veryfast with faster's subpixel search and trellis above, both with
  deblocking one step stronger and adaptive quantisation at 0.7; high profile, zerolatency),
- h264-before: the stream's settings before 2026-12-04's second change (adaptive quantisation
  at x264's default strength 1.0; above 320x240 veryfast's subpixel search, no trellis),
- h264-psnr: the stream tuned for the PSNR figure (x264's psnr tune: no adaptive quantisation
  or psychovisual optimisation; chroma quantised 6 steps finer): fewer bytes at equal PSNR,
  a lower SSIM than JPEG's.
The H.264 bytes, time and SSIM at JPEG q90's PSNR (and bytes at its SSIM) are interpolated
between the CRFs around it. Writes bench/results/codec_bench.csv, codec_equal_psnr.csv and
codec_bench.png (rate-distortion in PSNR and in SSIM)."""
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


def at(rows, key, target, field):
    """`field` of the H.264 rows interpolated where `key` (psnr_mean or ssim_mean) equals
    `target` (bytes log-linearly)."""
    rows = sorted(rows, key=lambda r: r[key])
    for lo, hi in zip(rows, rows[1:]):
        if lo[key] <= target <= hi[key]:
            t = (target - lo[key]) / (hi[key] - lo[key])
            if field == "bytes_mean":
                return math.exp((1 - t) * math.log(lo[field]) + t * math.log(hi[field]))
            return (1 - t) * lo[field] + t * hi[field]
    raise SystemExit(f"codec_bench: {key} {target:.4f} outside the CRFs' range")


VARIANTS = (("h264", "stream", "50,70,80,90,95"),
            ("h264-before", "stream:::aq-strength=1/BEFORE", "90"),
            ("h264-psnr", "stream::psnr,zerolatency:chroma-qp-offset=-6", "90"))


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
        for name, setting, qualities in VARIANTS:
            # Above 320x240 the stream's subpixel search and trellis were veryfast's own.
            setting = setting.replace("/BEFORE", "/subme=2/trellis=0" if size[0] > 320 else "")
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
        for name, _, _ in VARIANTS:
            h264 = [r for r in rows if r["codec"] == name]
            psnr = jpeg["psnr_mean"]
            bytes_h264 = at(h264, "psnr_mean", psnr, "bytes_mean")
            ms_h264 = at(h264, "psnr_mean", psnr, "encode_ms_median")
            ssim_h264 = at(h264, "psnr_mean", psnr, "ssim_mean")
            bytes_at_ssim = at(h264, "ssim_mean", jpeg["ssim_mean"], "bytes_mean")
            summary.append([f"{size[0]}x{size[1]}", name, round(psnr, 2),
                            round(jpeg["bytes_mean"]), round(jpeg["encode_ms_median"], 3),
                            round(jpeg["ssim_mean"], 5), round(bytes_h264), round(ms_h264, 3),
                            round(ssim_h264, 5), round(jpeg["bytes_mean"] / bytes_h264, 2),
                            round(jpeg["bytes_mean"] / bytes_at_ssim, 2)])
            print(f"{size[0]}x{size[1]}: JPEG q90 {psnr:.2f} dB SSIM {jpeg['ssim_mean']:.4f}, "
                  f"{jpeg['bytes_mean']:.0f} B, {jpeg['encode_ms_median']:.2f} ms; {name} at "
                  f"that PSNR {bytes_h264:.0f} B, {ms_h264:.2f} ms, SSIM {ssim_h264:.4f}: "
                  f"{jpeg['bytes_mean'] / bytes_h264:.2f}x fewer bytes "
                  f"({jpeg['bytes_mean'] / bytes_at_ssim:.2f}x at equal SSIM)")
    with open(os.path.join(a.out, "codec_bench.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(table[0].keys()))
        w.writeheader()
        w.writerows(table)
    with open(os.path.join(a.out, "codec_equal_psnr.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["size", "h264", "psnr_db", "jpeg_q90_bytes", "jpeg_q90_ms", "jpeg_q90_ssim",
                    "h264_bytes", "h264_ms", "h264_ssim", "bytes_ratio", "bytes_ratio_equal_ssim"])
        w.writerows(summary)
    plot(a.out, table)


def plot(out, table):
    data = os.path.join(out, "codec_bench.dat")
    codecs = ("jpeg", "h264", "h264-before", "h264-psnr")
    with open(data, "w") as f:
        for codec in codecs:
            for size in ((320, 180), (640, 360)):
                f.write(f"# {codec} {size[0]}x{size[1]}\n")
                for r in sorted((r for r in table if r["codec"] == codec and
                                 r["width"] == size[0]), key=lambda r: r["bytes_mean"]):
                    f.write(f"{r['bytes_mean'] / 1024:.3f} {r['psnr_mean']:.3f} "
                            f"{r['ssim_mean']:.5f}\n")
                f.write("\n\n")
    titles = ("JPEG", "H.264 stream", "H.264 stream before (aq 1, veryfast search)",
              "H.264 psnr tune")
    curves = ", ".join(f"'{data}' index {2 * i + j} using 1:COLUMN with linespoints dt {1 + j} "
                       f"lc {i + 1} title '{titles[i]} {size}'"
                       for i in range(len(codecs)) for j, size in enumerate(("320x180", "640x360")))
    png = os.path.join(out, "codec_bench.png")
    subprocess.run(["gnuplot", "-e", f"""set terminal pngcairo size 1200,460; set output '{png}';
        set multiplot layout 1,2 title 'JPEG (q 50-95) vs H.264 (CRF 9-30, 1 thread): demo frames';
        set logscale x; set xlabel 'KiB per frame'; set key bottom right font ',8'; set grid;
        set ylabel 'PSNR (dB) against the frame sent';
        plot {curves.replace('COLUMN', '2')};
        set ylabel 'SSIM (luma) against the frame sent';
        plot {curves.replace('COLUMN', '3')};
        unset multiplot"""], check=True)
    os.remove(data)


if __name__ == "__main__":
    main()
