"""A real farm on loopback for the HTTP port's tests: a coordinator with --http-port, tracers
and optionally the native headless client, each a process; stopped (and their logs shown on
failure) when the test ends."""
import os
import re
import ssl
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

SECRET = "web-test-secret"


class Farm:
    def __init__(self, build, scene="builtin:cornell", tracers=1, size=(160, 90),
                 extra=(), native_client=False, client_args=(), cafile=None):
        self.build = build
        # HTTPS: requests verify the server against this certificate.
        self.ssl = ssl.create_default_context(cafile=cafile) if cafile else None
        self.dir = tempfile.mkdtemp(prefix="pathfarm-web-")
        self.stats_csv = os.path.join(self.dir, "stats.csv")
        self.tracer_csv = os.path.join(self.dir, "tracers.csv")
        self.procs = []
        env = dict(os.environ, PATHFARM_SECRET=SECRET)
        self.env = env
        log = open(os.path.join(self.dir, "coordinator.log"), "w+")
        self.procs.append((subprocess.Popen(
            [f"{build}/coordinator/pathfarm-coordinator", "--scene", scene,
             "--tracer-port", "0", "--client-port", "0", "--http-port", "0",
             "--bind", "127.0.0.1", "--width", str(size[0]), "--height", str(size[1]),
             "--target-fps", "10", "--fps", "10", "--stats-csv", self.stats_csv,
             "--tracer-stats-csv", self.tracer_csv, "--min-tracers", str(tracers), *extra],
            stdout=log, stderr=subprocess.STDOUT, env=env), log))
        text = self._wait_for(log, r"browser client: (\S+)")
        self.url = re.search(r"browser client: (\S+)", text).group(1)
        self.base = self.url.split("?")[0]
        self.token = self.url.split("token=")[1]
        ports = re.search(r"tracer_port=(\d+) client_port=(\d+)", text)
        for k in range(tracers):
            self._spawn(f"tracer{k}", [f"{build}/tracer-node/pathfarm-tracer", "--coordinator",
                                       f"127.0.0.1:{ports.group(1)}", "--threads", "1",
                                       "--name", f"tracer{k}"])
        if native_client:
            self._spawn("client", [f"{build}/client/pathfarm-client", "--connect",
                                   f"127.0.0.1:{ports.group(2)}", "--headless",
                                   "--turn-rate", "0.3", *client_args])

    def _spawn(self, name, argv):
        log = open(os.path.join(self.dir, name + ".log"), "w+")
        self.procs.append((subprocess.Popen(argv, stdout=log, stderr=subprocess.STDOUT,
                                            env=self.env), log))

    def _wait_for(self, log, pattern, seconds=30):
        deadline = time.time() + seconds
        while time.time() < deadline:
            log.seek(0)
            text = log.read()
            if re.search(pattern, text):
                return text
            if self.procs[0][0].poll() is not None:
                break
            time.sleep(0.05)
        raise RuntimeError(f"coordinator: no '{pattern}' in its log:\n{text}")

    def wait_log(self, pattern, seconds=30):
        """Waits for a line of the coordinator's log."""
        self._wait_for(self.procs[0][1], pattern, seconds)

    def get(self, path, token=True, cookie=None):
        """(status, body) of a GET; token=True adds ?token=, a string uses that token."""
        url = self.base.rstrip("/") + path
        if token:
            sep = "&" if "?" in path else "?"
            url += f"{sep}token={self.token if token is True else token}"
        request = urllib.request.Request(url)
        if cookie:
            request.add_header("Cookie", cookie)
        try:
            with urllib.request.urlopen(request, timeout=10, context=self.ssl) as r:
                return r.status, r.read().decode(), dict(r.headers)
        except urllib.error.HTTPError as e:
            return e.code, e.read().decode(), dict(e.headers)

    def frames_in_csv(self):
        with open(self.stats_csv) as f:
            return max(0, len(f.read().splitlines()) - 1)

    def wait_frames(self, n, seconds=60):
        deadline = time.time() + seconds
        while time.time() < deadline:
            if os.path.exists(self.stats_csv) and self.frames_in_csv() >= n:
                return
            time.sleep(0.1)
        raise RuntimeError(f"fewer than {n} frames in {seconds} s\n{self.logs()}")

    def logs(self):
        out = []
        for p, log in self.procs:
            log.seek(0)
            out.append(f"--- {p.args[0]}\n{log.read()[-3000:]}")
        return "\n".join(out)

    def stop(self):
        for p, _ in reversed(self.procs):
            if p.poll() is None:
                p.terminate()
        for p, log in self.procs:
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
            log.close()

    def __enter__(self):
        return self

    def __exit__(self, kind, value, tb):
        if kind is not None:
            print(self.logs(), file=sys.stderr)
        self.stop()
