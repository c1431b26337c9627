#!/usr/bin/env python3
"""End-to-end test of clients/python/granulab_client.py against a real granulabd (standard library only).

The daemon binary comes from $GRANULABD (set by CTest) or ../../build/granulabd relative to this file.
"""

import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import unittest
import urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "clients", "python"))

from granulab_client import Client, GranulabError  # noqa: E402

DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")
TINY = {"experiment": "two_cube_sliding", "grain": {"edge_spheres": 3},
        "loading": {"rate_number": 1e-3}, "output": {"curve_points": 10}}
CSV_HEADER = "slide_over_size,normal_over_p0,tangential_over_p0,normal_force,tangential_force"


def free_port():
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class PythonClientTest(unittest.TestCase):
    def setUp(self):
        if not os.access(DAEMON, os.X_OK):
            self.fail(f"granulabd not found at {DAEMON} (build it, or set GRANULABD)")
        self.tmp = tempfile.mkdtemp(prefix="granulab_pyclient_")
        self.log = open(os.path.join(self.tmp, "daemon.log"), "w+")
        self.port = free_port()
        env = dict(os.environ, OMP_WAIT_POLICY="passive")
        self.proc = subprocess.Popen(
            [DAEMON, "--port", str(self.port), "--db", os.path.join(self.tmp, "test.db"), "--workers", "1"],
            stdout=self.log, stderr=subprocess.STDOUT, env=env)
        self.client = Client(f"http://127.0.0.1:{self.port}")
        deadline = time.monotonic() + 20
        while True:
            if self.proc.poll() is not None:
                self.fail(f"granulabd exited with {self.proc.returncode}:\n{self._log()}")
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{self.port}/v1/health", timeout=2) as r:
                    if r.status == 200:
                        break
            except OSError:
                pass
            if time.monotonic() > deadline:
                self.fail(f"granulabd did not answer /v1/health within 20 s:\n{self._log()}")
            time.sleep(0.1)

    def tearDown(self):
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self.log.close()
        shutil.rmtree(self.tmp, ignore_errors=True)

    def _log(self):
        self.log.flush()
        self.log.seek(0)
        return self.log.read()[-4000:]

    def test_health(self):
        h = self.client.health()
        self.assertEqual(h.get("status"), "ok")

    def test_experiments_describe_the_fields_a_spec_may_hold(self):
        experiments = {e["name"]: e for e in self.client.experiments()}
        self.assertIn("two_cube_sliding", experiments)
        fields = {f["field"]: f for f in experiments["two_cube_sliding"]["fields"]}
        self.assertEqual(fields["grain.edge_spheres"]["default"], 10)
        self.assertEqual(fields["grain.size"]["unit"], "m")
        columns = [c["name"] for c in experiments["two_cube_sliding"]["curve_columns"]]
        self.assertEqual(columns, CSV_HEADER.split(","))

    def test_submit_wait_curve_list(self):
        job = self.client.submit(TINY)
        self.assertIsInstance(job, int)
        seen = []
        final = self.client.wait(job, timeout=60, poll=0.1, on_progress=seen.append)
        self.assertEqual(final["status"], "succeeded")
        self.assertTrue(seen)
        self.assertEqual(final["id"], job)

        curve = self.client.curve(job)
        self.assertEqual(curve["columns"], CSV_HEADER.split(","))
        for name in curve["columns"]:
            self.assertEqual(len(curve[name]), len(curve["slide_over_size"]), name)
        self.assertAlmostEqual(curve["normal_over_p0"][0], 1.0, places=9)

        csv = self.client.curve_csv(job)
        lines = csv.strip().splitlines()
        self.assertEqual(lines[0], CSV_HEADER)
        self.assertEqual(len(lines) - 1, len(curve["slide_over_size"]))

        self.assertIsInstance(self.client.snapshots(job), list)
        self.assertIn(job, [j["id"] for j in self.client.list()])
        self.assertIn(job, [j["id"] for j in self.client.list(status="succeeded")])
        self.assertNotIn(job, [j["id"] for j in self.client.list(status="queued")])

        # A finished job cannot be cancelled: 409.
        with self.assertRaises(GranulabError) as ctx:
            self.client.cancel(job)
        self.assertEqual(ctx.exception.status, 409)

        # reuse=true returns the stored result for the identical spec.
        again = self.client.submit(TINY, reuse=True)
        self.assertEqual(again, job)

    def test_priority_delete_and_owner_filter(self):
        # A long job holds the one worker, so the second stays queued while its priority changes.
        slow = self.client.submit(dict(TINY, loading={"rate_number": 1e-8}, output={"curve_points": 1}))
        queued = self.client.submit(TINY)
        self.assertEqual(self.client.set_priority(queued, 7)["priority"], 7)
        self.assertEqual(self.client.status(queued)["priority"], 7)
        with self.assertRaises(GranulabError) as ctx:
            self.client.delete(queued)  # still queued: cancel first
        self.assertEqual(ctx.exception.status, 409)
        self.client.cancel(queued)
        self.assertTrue(self.client.delete(queued)["deleted"])
        with self.assertRaises(GranulabError) as ctx:
            self.client.status(queued)
        self.assertEqual(ctx.exception.status, 404)
        self.assertEqual([j["id"] for j in self.client.list(owner="nobody")], [])
        self.client.cancel(slow)
        with self.assertRaises(GranulabError) as ctx:  # wait() raises for a job that did not succeed
            self.client.wait(slow, timeout=10)
        self.assertEqual(ctx.exception.code, "cancelled")

    def test_sweep(self):
        sweep_id, jobs = self.client.submit_sweep(TINY, {"material.friction": [0.1, 0.2, 0.3]}, label="friction")
        self.assertEqual(len(jobs), 3)
        for job in jobs:
            self.assertEqual(self.client.wait(job, timeout=60)["status"], "succeeded")
        view = self.client.sweep(sweep_id)
        self.assertEqual(view["counts"], {"succeeded": 3})
        self.assertEqual(sorted(j["values"]["material.friction"] for j in view["jobs"]), [0.1, 0.2, 0.3])
        self.assertIn(sweep_id, [s["id"] for s in self.client.sweeps()])
        with self.assertRaises(GranulabError) as ctx:
            self.client.submit_sweep(TINY, {"material.friction": [0.1, -5]})
        self.assertEqual(ctx.exception.field, "vary.material.friction")

    def test_submit_from_file(self):
        path = os.path.join(self.tmp, "spec.json")
        with open(path, "w") as f:
            json.dump(TINY, f)
        job = self.client.submit(path, priority=5)
        self.assertEqual(self.client.wait(job, timeout=60, poll=0.1)["status"], "succeeded")

    def test_bad_spec_is_400_with_field(self):
        bad = dict(TINY, grain={"edge_spheres": -1})
        with self.assertRaises(GranulabError) as ctx:
            self.client.submit(bad)
        e = ctx.exception
        self.assertEqual(e.status, 400)
        self.assertEqual(e.field, "grain.edge_spheres")
        self.assertTrue(e.message)
        self.assertIn("400", str(e))
        self.assertIn("grain.edge_spheres", str(e))

    def test_unknown_id_is_404(self):
        for call in (self.client.status, self.client.curve, self.client.cancel):
            with self.assertRaises(GranulabError) as ctx:
                call(987654)
            self.assertEqual(ctx.exception.status, 404, call.__name__)

    def test_command_line(self):
        script = os.path.join(ROOT, "clients", "python", "granulab_client.py")
        server = f"http://127.0.0.1:{self.port}"
        out = subprocess.run([sys.executable, script, "--server", server, "health"],
                             capture_output=True, text=True, timeout=30)
        self.assertEqual(out.returncode, 0, out.stderr)
        self.assertEqual(json.loads(out.stdout)["status"], "ok")
        out = subprocess.run([sys.executable, script, "--server", server, "status", "987654"],
                             capture_output=True, text=True, timeout=30)
        self.assertEqual(out.returncode, 1)
        self.assertIn("404", out.stderr)


if __name__ == "__main__":
    unittest.main()
