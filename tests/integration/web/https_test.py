#!/usr/bin/python3
"""The HTTP port with a certificate (docs/security.md, "The HTTP port"): --https-cert and
--https-key make it HTTPS and WSS. A self-signed certificate made here with openssl: the printed
URL is https, /healthz answers over a verified TLS connection, the token is still required,
the WebSocket carries frames over WSS, plain HTTP on that port gets no answer, and a missing
certificate file is a one-line error. Usage: https_test.py BUILD_DIR"""
import os
import socket
import ssl
import subprocess
import sys
import tempfile
import unittest

import websocket

import web_farm

BUILD = None


def make_certificate(folder):
    cert, key = os.path.join(folder, "cert.pem"), os.path.join(folder, "key.pem")
    subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-keyout", key,
                    "-out", cert, "-days", "1", "-subj", "/CN=127.0.0.1",
                    "-addext", "subjectAltName=IP:127.0.0.1"], check=True, capture_output=True)
    return cert, key


class Https(unittest.TestCase):
    def test_the_port_serves_https_and_wss(self):
        with tempfile.TemporaryDirectory() as folder:
            cert, key = make_certificate(folder)
            with web_farm.Farm(BUILD, extra=("--https-cert", cert, "--https-key", key),
                               cafile=cert) as farm:
                self.assertTrue(farm.url.startswith("https://127.0.0.1:"), farm.url)
                status, body, _ = farm.get("/healthz", token=False)
                self.assertEqual((status, body.strip()), (200, "ok"))
                self.assertEqual(farm.get("/metrics", token=False)[0], 403)
                self.assertEqual(farm.get("/metrics")[0], 200)
                farm.wait_frames(2)
                ws = websocket.create_connection(
                    farm.base.replace("https://", "wss://").rstrip("/") + f"/ws?token={farm.token}",
                    timeout=10, sslopt={"ca_certs": cert})
                message = ws.recv()
                ws.close()
                self.assertEqual(message[:4], b"PFWF", "a frame over WSS")
                port = int(farm.base.rstrip("/").rsplit(":", 1)[1])
                with socket.create_connection(("127.0.0.1", port), timeout=5) as plain:
                    plain.sendall(b"GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
                    try:
                        reply = plain.recv(100)
                    except (ConnectionResetError, socket.timeout):
                        reply = b""
                    self.assertFalse(reply.startswith(b"HTTP/1.1 200"), reply)

    def test_a_missing_certificate_is_a_one_line_error(self):
        env = dict(os.environ, PATHFARM_SECRET="x")
        r = subprocess.run([f"{BUILD}/coordinator/pathfarm-coordinator", "--scene", "builtin:cornell",
                            "--tracer-port", "0", "--client-port", "0", "--http-port", "0",
                            "--https-cert", "/no/such/cert.pem", "--https-key", "/no/such/key.pem",
                            "--frames", "1"], capture_output=True, text=True, env=env, timeout=30)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("--https-cert /no/such/cert.pem", r.stderr + r.stdout)


if __name__ == "__main__":
    BUILD = sys.argv.pop(1)
    unittest.main()
