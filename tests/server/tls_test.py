#!/usr/bin/python3
"""HTTPS end to end (issue 25, point 6): granulabd --tls-cert/--tls-key with a self-signed certificate made
here by `openssl`, on loopback with a real SQLite file and tokens:

- the Python client (ca_file) and the CLI (GRANULAB_CA_FILE) submit, wait and read a job over HTTPS;
- a client that does not trust the certificate is refused by its own TLS check, with a message that says so;
- plain HTTP to the TLS port, garbage bytes, and a client that never finishes its handshake are closed, and
  the daemon goes on serving;
- no "tokens in clear" warning with TLS on.

Run from the repository root:  /usr/bin/python3 tests/server/tls_test.py
Standard library only; needs the openssl command (skips, exit 77, without it).
"""
import http.client
import json
import os
import shutil
import socket
import ssl
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "clients", "python"))
sys.path.insert(0, os.path.dirname(HERE))
from granulab_client import Client, GranulabError  # noqa: E402
import skip_aware  # noqa: E402

DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")
CLI = os.path.join(os.path.dirname(DAEMON), "granulab")
TINY = {"experiment": "two_cube_sliding", "grain": {"edge_spheres": 2}, "loading": {"rate_number": 0.1},
        "output": {"curve_points": 4}, "label": "over tls"}


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class TlsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not shutil.which("openssl"):
            raise unittest.SkipTest("no openssl command to make a certificate")
        cls.dir = tempfile.mkdtemp(prefix="granulab_tls_")
        cls.cert, cls.key = os.path.join(cls.dir, "cert.pem"), os.path.join(cls.dir, "key.pem")
        subprocess.run(["openssl", "req", "-x509", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1",
                        "-nodes", "-keyout", cls.key, "-out", cls.cert, "-days", "2", "-subj", "/CN=127.0.0.1",
                        "-addext", "subjectAltName=IP:127.0.0.1"], check=True, capture_output=True)
        tokens = os.path.join(cls.dir, "tokens")
        cls.token = subprocess.run([DAEMON, "token", "add", "alice", "--token-file", tokens], check=True,
                                   capture_output=True, text=True).stdout.strip()
        cls.port = free_port()
        cls.url = "https://127.0.0.1:%d" % cls.port
        cls.log_path = os.path.join(cls.dir, "daemon.log")
        cls.log = open(cls.log_path, "w")
        cls.daemon = subprocess.Popen([DAEMON, "--host", "0.0.0.0", "--port", str(cls.port), "--db",
                                       os.path.join(cls.dir, "g.db"), "--workers", "1", "--threads", "1",
                                       "--token-file", tokens, "--tls-cert", cls.cert, "--tls-key", cls.key,
                                       "--keep-alive-timeout", "1", "--speed-probe-seconds", "0"],
                                      stdout=cls.log, stderr=subprocess.STDOUT)
        cls.client = Client(cls.url, token=cls.token, ca_file=cls.cert)
        for _ in range(200):
            try:
                cls.client.health()
                break
            except GranulabError:
                time.sleep(0.05)

    @classmethod
    def tearDownClass(cls):
        if getattr(cls, "daemon", None):
            cls.daemon.terminate()
            cls.daemon.wait(timeout=30)
            cls.log.close()
        shutil.rmtree(getattr(cls, "dir", ""), ignore_errors=True)

    def log_text(self):
        self.log.flush()
        with open(self.log_path) as f:
            return f.read()

    def test_the_python_client_runs_a_job_over_https(self):
        job = self.client.submit(TINY)
        self.assertEqual(self.client.wait(job, timeout=60)["status"], "succeeded")
        self.assertGreater(len(self.client.curve_csv(job).splitlines()), 3)
        self.assertIn("listening on https://", self.log_text())
        self.assertNotIn("in clear", self.log_text())

    def test_the_cli_runs_a_job_over_https(self):
        env = dict(os.environ, GRANULAB_SERVER=self.url, GRANULAB_TOKEN=self.token, GRANULAB_CA_FILE=self.cert)
        made = subprocess.run([CLI, "submit", "-"], input=json.dumps(TINY), env=env, capture_output=True, text=True,
                              timeout=60)
        self.assertEqual(made.returncode, 0, made.stderr)
        job = made.stdout.strip()
        self.assertEqual(subprocess.run([CLI, "wait", job], env=env, capture_output=True, timeout=60).returncode, 0)
        status = subprocess.run([CLI, "status", job], env=env, capture_output=True, text=True, timeout=60)
        self.assertIn("succeeded", status.stdout)
        # Without the lab's certificate the CLI refuses the server and says what to give.
        env.pop("GRANULAB_CA_FILE")
        refused = subprocess.run([CLI, "list"], env=env, capture_output=True, text=True, timeout=60)
        self.assertNotEqual(refused.returncode, 0)
        self.assertIn("ca-file", refused.stderr)

    def test_a_client_that_does_not_trust_the_certificate_is_refused_by_its_own_check(self):
        with self.assertRaises(GranulabError) as refused:
            Client(self.url, token=self.token, retries=0).health()
        self.assertEqual(refused.exception.code, "tls")

    def test_plain_http_garbage_and_unfinished_handshakes_are_closed_and_the_daemon_goes_on(self):
        plain = http.client.HTTPConnection("127.0.0.1", self.port, timeout=5)
        with self.assertRaises((http.client.HTTPException, ConnectionError, OSError)):
            plain.request("GET", "/v1/health")
            plain.getresponse().read()
        plain.close()
        with socket.create_connection(("127.0.0.1", self.port), timeout=5) as s:
            s.sendall(b"\x16\x03\x01\x00\x05hello-not-tls" * 10)
            s.settimeout(5)
            try:
                self.assertEqual(s.recv(4096)[:1] in (b"", b"\x15"), True)  # closed, or a TLS alert
            except ConnectionError:
                pass
        # A client that opens and never speaks is closed after the keep-alive timeout (1 s here).
        start = time.time()
        with socket.create_connection(("127.0.0.1", self.port), timeout=10) as s:
            try:
                self.assertEqual(s.recv(4096), b"")
            except ConnectionError:
                pass
        self.assertLess(time.time() - start, 5)
        self.assertEqual(self.client.health()["status"], "ok")
        self.assertIsNone(self.daemon.poll())


if __name__ == "__main__":
    skip_aware.main()
