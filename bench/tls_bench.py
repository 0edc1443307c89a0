#!/usr/bin/env python3
"""TLS cost on the farm (issue: secure links): the same batch frames of builtin:default rendered
by a coordinator, two tracers x 1 thread and a headless JPEG client on loopback, with TLS (the
default) and with --insecure-plaintext on every end, alternated round by round (ABBA) so that
machine noise hits both alike. Frames/s as medians and the ratio; bytes on the tracer links per
frame; the error figure: the TLS run's frames against the plaintext run's (RMSE; the transport
must not change a pixel). CSV and a gnuplot PNG under bench/results."""
import argparse
import csv
import os
import re
import statistics
import subprocess
import tempfile

from bench_common import ROOT, batch_mode, rmse, start, wait_for, write_csv


def farm(build, work, tls, width, height, spp, frames):
    os.environ["PATHFARM_SECRET"] = "tls-bench"
    plain = [] if tls else ["--insecure-plaintext"]
    coordinator = f"{build}/coordinator/pathfarm-coordinator"
    log = os.path.join(work, "coordinator.log")
    c = start([coordinator, "--scene", "builtin:default", "--tracer-port", "0", "--client-port", "0",
               "--width", str(width), "--height", str(height), "--spp", str(spp), "--frames", str(frames),
               "--min-tracers", "2", "--stats-csv", f"{work}/stats.csv", "--dump-frames", f"{work}/dump",
               *batch_mode(coordinator), *plain], log)
    tracer_port = wait_for(log, r"tracer_port=(\d+)", "tls_bench").group(1)
    client_port = wait_for(log, r"client_port=(\d+)", "tls_bench").group(1)
    client = start([f"{build}/client/pathfarm-client", "--connect", f"127.0.0.1:{client_port}", "--headless",
                    "--frames", str(frames), *plain], os.path.join(work, "client.log"))
    wait_for(log, r'"headless-client" connected', "tls_bench")
    tracers = [start([f"{build}/tracer-node/pathfarm-tracer", "--coordinator", f"127.0.0.1:{tracer_port}",
                      "--threads", "1", "--name", f"t{i}", "--max-reconnects", "0", *plain],
                     os.path.join(work, f"t{i}.log")) for i in range(2)]
    if c.wait(timeout=900) != 0:
        raise SystemExit(f"tls_bench: the coordinator failed:\n{open(log).read()[-1500:]}")
    for p in tracers + [client]:
        p.wait(timeout=60)
    fps = float(wait_for(log, r"fps=([0-9.]+)", "tls_bench").group(1))
    stats = list(csv.DictReader(open(f"{work}/stats.csv")))[1:]  # frame 0 carries the snapshot
    wire = statistics.mean(int(r["commit_bytes"]) + int(r["tile_bytes"]) for r in stats)
    insecure_warned = "INSECURE" in open(log).read()
    if insecure_warned == tls:
        raise SystemExit(f"tls_bench: the coordinator's INSECURE warning does not match tls={tls}")
    return fps, wire


def plot(out, summary):
    data = os.path.join(out, "tls_bench.dat")
    with open(data, "w") as f:
        for row in summary:
            f.write(f"{row[0]} {row[1]} {row[2]}\n")
    subprocess.run(["gnuplot", "-e", f"""set terminal pngcairo size 720,420;
        set output '{out}/tls_bench.png'; set style data histograms; set style histogram clustered;
        set style fill solid 0.8; set yrange [0:*]; set ylabel 'frames/s (median)'; set key top right;
        set title 'Farm frames/s with TLS 1.3 (PSK) vs --insecure-plaintext, 2 tracers x 1 thread + client';
        plot '{data}' using 2:xtic(1) title 'TLS', '' using 3 title 'plaintext'"""], check=True)
    os.remove(data)


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--frames", type=int, default=60)
    p.add_argument("--rounds", type=int, default=4)
    p.add_argument("--spp", type=int, default=1)
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    runs, summary = [], []
    for width, height in ((320, 180), (640, 360)):
        fps = {True: [], False: []}
        worst_rmse = 0.0
        for r in range(a.rounds):
            order = (True, False) if r % 2 == 0 else (False, True)
            with tempfile.TemporaryDirectory() as tls_dir, tempfile.TemporaryDirectory() as plain_dir:
                for tls in order:
                    f, wire = farm(a.build, tls_dir if tls else plain_dir, tls, width, height, a.spp, a.frames)
                    fps[tls].append(f)
                    runs.append([f"{width}x{height}", r, "tls" if tls else "plaintext", f, round(wire)])
                    print(f"{width}x{height} round {r} {'tls' if tls else 'plaintext'}: {f:.2f} frames/s, "
                          f"{wire / 1024:.1f} KiB/frame on tracer links", flush=True)
                last = f"frame_{a.frames - 1:06d}.pfm"
                worst_rmse = max(worst_rmse, rmse(os.path.join(tls_dir, "dump", last),
                                                  os.path.join(plain_dir, "dump", last)))
        t, q = statistics.median(fps[True]), statistics.median(fps[False])
        summary.append([f"{width}x{height}", round(t, 2), round(q, 2), round(t / q, 3), worst_rmse])
        print(f"{width}x{height}: TLS {t:.2f} vs plaintext {q:.2f} frames/s: ratio {t / q:.3f}; "
              f"RMSE TLS vs plaintext frames {worst_rmse}")
    write_csv(os.path.join(a.out, "tls_bench_runs.csv"), ["size", "round", "mode", "fps", "tracer_link_bytes"],
              runs)
    write_csv(os.path.join(a.out, "tls_bench.csv"),
              ["size", "fps_tls", "fps_plaintext", "ratio", "rmse_tls_vs_plaintext"], summary)
    plot(a.out, summary)


if __name__ == "__main__":
    main()
