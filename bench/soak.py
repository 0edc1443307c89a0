#!/usr/bin/env python3
"""Soak benchmark (issue: secure links, item 4; not CI): the real-time farm for --minutes
(default 30) under churn and faults. builtin:default's game at 10 frames/s, 320x180; tracer A
connects directly, tracer B through a fault proxy (pathfarm-fault-proxy --random-faults:
stalls, resets mid-message, half-open links, latency); every 40-120 s one tracer is killed and
restarted 2-10 s later; a long-lived client watches through a second fault proxy and
reconnects; short-lived clients join and leave every 15-45 s. Every 5 s it samples the
coordinator's RSS and open file descriptors and the frames shown.

Records frames delivered and frames lost (a frame number missing from the stats CSV, or a
frame the coordinator abandoned: must be 0), whether RSS levels off (median of the last
quarter against the second quarter) and fds stay bounded. Writes bench/results/soak.csv
(samples), soak_events.csv, soak_summary.csv and soak.png."""
import argparse
import csv
import os
import random
import signal
import socket
import statistics
import subprocess
import tempfile
import time

from bench_common import ROOT, start, wait_for, write_csv


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def rss_mb(pid):
    for line in open(f"/proc/{pid}/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return 0.0


def frames_shown(path):
    if not os.path.exists(path):
        return []
    return [int(r["frame"]) for r in csv.DictReader(open(path)) if r.get("frame", "").isdigit()]


class Soak:
    def __init__(self, a, work):
        self.a, self.work, self.t0 = a, work, time.time()
        self.rng = random.Random(a.seed)
        self.events = []
        os.environ["PATHFARM_SECRET"] = "soak-secret"
        b = a.build
        self.coordinator = start([f"{b}/coordinator/pathfarm-coordinator", "--scene", "builtin:default",
                                  "--tracer-port", "0", "--client-port", "0", "--width", "320", "--height", "180",
                                  "--target-fps", "10", "--fps", "10", "--frames", "0", "--deadline-ms", "2000",
                                  "--stats-csv", f"{work}/stats.csv"], f"{work}/coordinator.log")
        log = f"{work}/coordinator.log"
        self.tracer_port = int(wait_for(log, r"tracer_port=(\d+)", "soak").group(1))
        self.client_port = int(wait_for(log, r"client_port=(\d+)", "soak").group(1))
        self.proxy_ports = (free_port(), free_port())
        self.proxies = [start([f"{b}/tools/pathfarm-fault-proxy", "--listen", str(port), "--target", str(target),
                               "--random-faults", str(every), "--seed", str(a.seed + i)], f"{work}/proxy{i}.log")
                        for i, (port, target, every) in enumerate(
                            ((self.proxy_ports[0], self.tracer_port, 20),
                             (self.proxy_ports[1], self.client_port, 30)))]
        time.sleep(0.5)
        self.tracers = {"a": self.tracer("a", self.tracer_port), "b": self.tracer("b", self.proxy_ports[0])}
        self.watcher = self.client("watcher", self.proxy_ports[1], 0, ["--reconnect-seconds", "30"])
        self.visitors = []

    def event(self, what):
        self.events.append((round(time.time() - self.t0, 1), what))
        print(f"[{self.events[-1][0]:7.1f} s] {what}", flush=True)

    def tracer(self, name, port):
        return start([f"{self.a.build}/tracer-node/pathfarm-tracer", "--coordinator", f"127.0.0.1:{port}",
                      "--threads", "1", "--name", name], f"{self.work}/tracer_{name}.log")

    def client(self, name, port, frames, extra=()):
        return start([f"{self.a.build}/client/pathfarm-client", "--connect", f"127.0.0.1:{port}", "--headless",
                      "--frames", str(frames), "--turn-rate", "0.2", *extra], f"{self.work}/client_{name}.log")

    def run(self):
        samples = []
        end = self.t0 + self.a.minutes * 60
        next_kill = time.time() + self.rng.uniform(40, 120)
        next_visit = time.time() + self.rng.uniform(15, 45)
        restart = {}
        next_sample = time.time()
        while time.time() < end:
            now = time.time()
            if now >= next_kill:
                name = self.rng.choice(sorted(self.tracers))
                self.tracers[name].kill()
                self.tracers[name].wait()
                restart[name] = now + self.rng.uniform(2, 10)
                self.event(f"killed tracer {name}")
                next_kill = now + self.rng.uniform(40, 120)
            for name, at in list(restart.items()):
                if now >= at:
                    self.tracers[name] = self.tracer(name, self.tracer_port if name == "a" else self.proxy_ports[0])
                    del restart[name]
                    self.event(f"restarted tracer {name}")
            if now >= next_visit:
                frames = self.rng.randint(20, 200)
                self.visitors.append(self.client(f"visitor{len(self.visitors)}", self.client_port, frames))
                self.event(f"a client joins for {frames} frames")
                next_visit = now + self.rng.uniform(15, 45)
            if now >= next_sample:
                pid = self.coordinator.pid
                shown = frames_shown(f"{self.work}/stats.csv")
                samples.append([round(now - self.t0, 1), round(rss_mb(pid), 1), len(os.listdir(f"/proc/{pid}/fd")),
                                len(shown), sum(1 for v in self.visitors if v.poll() is None)])
                next_sample = now + 5
            if self.coordinator.poll() is not None:
                raise SystemExit(f"soak: the coordinator exited ({self.coordinator.returncode})")
            time.sleep(0.2)
        return samples

    def stop(self):
        self.coordinator.send_signal(signal.SIGTERM)
        self.coordinator.wait(timeout=30)
        for p in list(self.tracers.values()) + self.proxies + [self.watcher] + self.visitors:
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)
        for p in list(self.tracers.values()) + self.proxies + [self.watcher] + self.visitors:
            try:
                p.wait(timeout=15)
            except subprocess.TimeoutExpired:
                p.kill()


def summarize(work, samples):
    shown = frames_shown(f"{work}/stats.csv")
    # A lost frame is a number missing from the stats CSV (the coordinator skipped it).
    missing = (max(shown) + 1 - len(set(shown))) if shown else 0
    log = open(f"{work}/coordinator.log").read()
    taken_over = log.count("tracer(s) take its")  # every tracer of a frame left; not lost
    q = len(samples) // 4
    rss_q2 = statistics.median(s[1] for s in samples[q:2 * q]) if q else 0.0
    rss_q4 = statistics.median(s[1] for s in samples[3 * q:]) if q else 0.0
    fds = [s[2] for s in samples]
    faults = sum(open(f"{work}/proxy{i}.log").read().count("fault:") for i in range(2))
    reconnects = open(f"{work}/client_watcher.log").read().count("reconnected")
    return {"minutes": round(samples[-1][0] / 60, 1) if samples else 0, "frames_delivered": len(shown),
            "frames_lost": missing, "frames_taken_over": taken_over, "rss_mb_q2": rss_q2,
            "rss_mb_q4": rss_q4,
            "rss_growth_pct": round(100 * (rss_q4 / rss_q2 - 1), 1) if rss_q2 else 0.0,
            "fds_min": min(fds), "fds_max": max(fds), "faults_injected": faults,
            "watcher_reconnects": reconnects}


def plot(out):
    subprocess.run(["gnuplot", "-e", f"""set datafile separator ',';
        set terminal pngcairo size 1000,600; set output '{out}/soak.png'; set multiplot layout 2,1;
        set xlabel 'seconds'; set grid; set key top left;
        set title 'Soak: coordinator RSS (MB) and open file descriptors';
        plot '{out}/soak.csv' skip 1 using 1:2 with lines title 'RSS MB', '' skip 1 using 1:3 with lines title 'fds';
        set title 'Frames shown (cumulative) under tracer churn, client churn and injected faults';
        plot '{out}/soak.csv' skip 1 using 1:4 with lines title 'frames';
        unset multiplot"""], check=True)


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--minutes", type=float, default=30.0)
    p.add_argument("--seed", type=int, default=7)
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    with tempfile.TemporaryDirectory() as work:
        soak = Soak(a, work)
        try:
            samples = soak.run()
        finally:
            soak.stop()
        summary = summarize(work, samples)
    write_csv(os.path.join(a.out, "soak.csv"), ["t_s", "rss_mb", "fds", "frames", "visitors"], samples)
    write_csv(os.path.join(a.out, "soak_events.csv"), ["t_s", "event"], soak.events)
    write_csv(os.path.join(a.out, "soak_summary.csv"), list(summary), [list(summary.values())])
    plot(a.out)
    print(" ".join(f"{k}={v}" for k, v in summary.items()))
    if summary["frames_lost"] != 0:
        raise SystemExit("soak: frames were lost")


if __name__ == "__main__":
    main()
