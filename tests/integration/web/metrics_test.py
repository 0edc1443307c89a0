"""/metrics against the statistics CSVs of the same run, parsed by Prometheus' own text parser
(python3-prometheus-client), and the HTTP port's access control. Usage: metrics_test.py BUILD"""
import csv
import sys
import unittest

from prometheus_client.parser import text_string_to_metric_families

import web_farm

BUILD = sys.argv.pop(1) if len(sys.argv) > 1 else "build"
FRAME_BOUNDS = [0.01, 0.02, 0.033, 0.05, 0.067, 0.1, 0.15, 0.2, 0.3, 0.5, 1.0, 2.0]


def scrape(farm):
    status, body, headers = farm.get("/metrics")
    assert status == 200, status
    assert headers["Content-Type"].startswith("text/plain; version=0.0.4"), headers
    samples = {}
    for family in text_string_to_metric_families(body):
        for s in family.samples:
            samples[(s.name, tuple(sorted(s.labels.items())))] = s.value
    return samples


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


class MetricsTest(unittest.TestCase):
    def test_metrics_agree_with_the_stats_csv(self):
        with web_farm.Farm(BUILD, tracers=2, native_client=True) as farm:
            farm.wait_log(r'client "headless-client" connected')
            for at_least in (5, 15, 25):
                farm.wait_frames(at_least)
                m = scrape(farm)
                # Rows are written before the metrics count them: the CSV holds every frame
                # /metrics has counted, and possibly one or two more by now.
                frames = rows(farm.stats_csv)
                k = int(m[("pathfarm_frames_total", ())])
                self.assertGreaterEqual(len(frames), k)
                self.assertGreaterEqual(k, at_least - 1)
                self.check_frames(m, frames[:k])
                shown = {r["frame"] for r in frames[:k]}
                tracers = [r for r in rows(farm.tracer_csv) if r["frame"] in shown]
                self.check_tracers(m, frames[:k], tracers)
                self.assertEqual(m[("pathfarm_clients", (("kind", "native"),))], 1)
                self.assertEqual(m[("pathfarm_clients", (("kind", "browser"),))], 0)
            self.assertGreater(m[("pathfarm_client_frame_bytes_total", ())], 0)
            self.assertGreater(m[("pathfarm_input_latency_seconds_count", ())], 0)

    def check_frames(self, m, frames):
        rendered = [float(r["frame_ms"]) / 1000 for r in frames if int(r["spp"]) > 0]
        self.assertEqual(m[("pathfarm_frame_seconds_count", ())], len(rendered))
        self.assertAlmostEqual(m[("pathfarm_frame_seconds_sum", ())], sum(rendered),
                               delta=1e-5 * max(1.0, sum(rendered)))
        buckets = {float(labels[0][1]): v for (name, labels), v in m.items()
                   if name == "pathfarm_frame_seconds_bucket"}
        self.assertEqual(sorted(buckets), FRAME_BOUNDS + [float("inf")])
        for bound, count in buckets.items():
            self.assertEqual(count, sum(1 for t in rendered if t <= bound), bound)
        self.assertEqual(m[("pathfarm_commit_bytes_total", ())],
                         sum(int(r["commit_bytes"]) for r in frames))
        self.assertEqual(m[("pathfarm_tile_bytes_total", ())],
                         sum(int(r["tile_bytes"]) for r in frames))
        self.assertEqual(m[("pathfarm_tracers", ())], int(frames[-1]["tracers"]))

    def check_tracers(self, m, frames, tracers):
        last = [r for r in frames if int(r["spp"]) > 0][-1]
        names = {r["tracer"] for r in tracers if r["frame"] == last["frame"]}
        self.assertEqual(len(names), 2)
        for name in names:
            label = (("tracer", name),)
            self.assertEqual(m[("pathfarm_tracer_rows_total", label)],
                             sum(int(r["rows_delivered"]) for r in tracers if r["tracer"] == name))
            mine = [r for r in tracers if r["tracer"] == name and r["frame"] == last["frame"]][0]
            self.assertAlmostEqual(m[("pathfarm_tracer_busy_ratio", label)],
                                   float(mine["render_ms"]) / float(last["frame_ms"]), delta=1e-4)

    def test_every_route_but_healthz_needs_the_token(self):
        with web_farm.Farm(BUILD) as farm:
            self.assertEqual(farm.get("/healthz", token=False)[:2], (200, "ok\n"))
            for path in ("/", "/index.html", "/app.js", "/style.css", "/metrics", "/ws"):
                self.assertEqual(farm.get(path, token=False)[0], 403, path)
                self.assertEqual(farm.get(path, token="0" * 32)[0], 403, path)
                self.assertEqual(farm.get(path, token=farm.token[:-1])[0], 403, path)
            status, page, headers = farm.get("/")
            self.assertEqual(status, 200)
            self.assertIn("app.js", page)
            cookie = headers["Set-Cookie"].split(";")[0]
            self.assertEqual(cookie, f"pathfarm_token={farm.token}")
            self.assertIn("HttpOnly", headers["Set-Cookie"])
            self.assertEqual(farm.get("/app.js", token=False, cookie=cookie)[0], 200)
            self.assertEqual(farm.get("/metrics", token=False, cookie=cookie)[0], 200)
            self.assertEqual(farm.get("/nothing")[0], 404)


if __name__ == "__main__":
    unittest.main()
