#!/usr/bin/python3
"""Input-to-frame latency of the browser client against the native one, side by side in one
farm (issue: browser p50 on loopback within 10 ms of the native client's).

One coordinator (builtin:default, 320x180, 10 frames/s held), two tracers, the native headless
client turning (an input every 16 ms) and Debian's headless chromium on the HTTP port holding
an arrow key (an input per animation frame), both for the same seconds. Each measures from
sending an input to the arrival of the first frame that shows it. Writes
bench/results/browser_latency.csv (+ .png) and a screenshot of the page to docs/.

Run with Debian's python3 (python3-websocket): /usr/bin/python3 bench/browser_latency.py
"""
import argparse
import csv
import os
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "integration", "web"))
from bench_common import quantile  # noqa: E402
import cdp  # noqa: E402
import web_farm  # noqa: E402


def browser_latencies(browser, seconds):
    """Holds ArrowLeft for `seconds`, collecting every latency the page measured."""
    got, seen = [], 0
    common = {"code": "ArrowLeft", "key": "ArrowLeft", "windowsVirtualKeyCode": 37}
    browser.call("Input.dispatchKeyEvent", type="keyDown", **common)
    end = time.time() + seconds
    while time.time() < end:
        time.sleep(0.5)
        count, newest = browser.evaluate(
            "[window.pathfarm.latencyCount, window.pathfarm.latenciesMs]")
        fresh = count - seen
        got += newest[len(newest) - min(fresh, len(newest)):] if fresh > 0 else []
        seen = count
    browser.call("Input.dispatchKeyEvent", type="keyUp", **common)
    return got


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    p.add_argument("--seconds", type=float, default=30.0)
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--screenshot", default=os.path.join(ROOT, "docs", "browser_client.png"))
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    with web_farm.Farm(a.build, scene="builtin:default", tracers=2, size=(320, 180),
                       native_client=True) as farm:
        farm.wait_log(r'client "headless-client" connected')
        browser = cdp.Chromium()
        try:
            browser.call("Page.navigate", url=farm.url)
            browser.wait_until("window.pathfarm && window.pathfarm.frames >= 10")
            native_log = farm.procs[-1][1]
            browser_ms = browser_latencies(browser, a.seconds)
            browser.screenshot(a.screenshot)
        finally:
            browser.close()
        client = farm.procs[-1][0]
        client.send_signal(2)  # SIGINT: the native client prints its summary and exits
        client.wait(timeout=10)
        native_log.seek(0)
        text = native_log.read()
    fields = dict(kv.split("=") for kv in text.split() if "=" in kv and "_ms=" in kv)
    native = (float(fields["latency_p50_ms"]), float(fields["latency_p99_ms"]))
    browser = (quantile(browser_ms, 0.5), quantile(browser_ms, 0.99))
    rows = [("native", native[0], native[1]), ("browser", browser[0], browser[1])]
    path = os.path.join(a.out, "browser_latency.csv")
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["client", "latency_p50_ms", "latency_p99_ms"])
        w.writerows(rows)
    print(f"native  p50 {native[0]:.1f} ms  p99 {native[1]:.1f} ms")
    print(f"browser p50 {browser[0]:.1f} ms  p99 {browser[1]:.1f} ms  "
          f"({len(browser_ms)} inputs, mean {statistics.mean(browser_ms):.1f} ms)")
    print(f"browser - native p50: {browser[0] - native[0]:+.1f} ms; wrote {path}, {a.screenshot}")
    plot = path.replace(".csv", ".png")
    subprocess.run(["gnuplot", "-e", f"""set terminal pngcairo size 640,360; set output '{plot}';
        set datafile separator ','; set style data histograms; set style fill solid 0.8;
        set ylabel 'input-to-frame latency (ms)'; set key top left; set yrange [0:*];
        set title 'Loopback, builtin:default 320x180 at 10 frames/s, both clients at once';
        plot '{path}' using 2:xtic(1) title 'p50', '' using 3 title 'p99'"""], check=True)


if __name__ == "__main__":
    main()
