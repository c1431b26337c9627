#!/usr/bin/python3
"""Checkpoints at scale (issue 25, point 1), on a real granulabd with a real SQLite file: a crystal of about
5 million spheres, whose checkpoint is stored in several 16 MiB chunks; the daemon
is killed (-9) once a checkpoint is stored, started again, resumes the job from it and finishes with, byte for
byte, the curve of an uninterrupted `granulab run` of the same spec. The daemon's peak memory (VmHWM) in both
lives is compared with the uninterrupted run's: a checkpoint may add only its chunks, not a copy of the state.

Slow (several minutes, about 3 GB of memory and disk): ctest label `slow`.
Run from the repository root:  /usr/bin/python3 tests/server/checkpoint_scale_test.py
Standard library only; the binaries come from $GRANULABD (set by CTest) or build/.
"""
import json
import os
import shutil
import signal
import socket
import sqlite3
import subprocess
import sys
import tempfile
import threading
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "clients", "python"))
sys.path.insert(0, os.path.dirname(HERE))
from granulab_client import Client  # noqa: E402
import skip_aware  # noqa: E402

DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")
CLI = os.path.join(os.path.dirname(DAEMON), "granulab")
# The reference crystal's grains (N_e = 10, 974 spheres each), 16 x 36 x 9 of them: 5,048,000 spheres, loaded
# a little way after its confinement.
SPEC = {"experiment": "crystal_compression", "grain": {"edge_spheres": 10},
        "crystal": {"grains_x": 16, "rows_z": 36, "layers_y": 9},
        "loading": {"confining_pressure": 60e3, "max_strain": float(os.environ.get("SCALE_MAX_STRAIN", "2e-4"))},
        "output": {"curve_points": 4, "snapshot_strains": []}, "run": {"threads": 2}}


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Peak:
    """The largest VmHWM of a process, sampled every 50 ms until stop()."""

    def __init__(self, pid):
        self.pid, self.bytes, self._stop = pid, 0, threading.Event()
        self._thread = threading.Thread(target=self._run)
        self._thread.start()

    def _run(self):
        while not self._stop.is_set():
            try:
                with open(f"/proc/{self.pid}/status") as f:
                    for line in f:
                        if line.startswith("VmHWM:"):
                            self.bytes = max(self.bytes, int(line.split()[1]) * 1024)
            except OSError:
                pass
            time.sleep(0.05)

    def stop(self):
        self._stop.set()
        self._thread.join()
        return self.bytes


class CheckpointScaleTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="granulab_ckscale_")
        self.db = os.path.join(self.dir, "g.db")
        self.port = free_port()
        self.daemon = None

    def tearDown(self):
        if self.daemon and self.daemon.poll() is None:
            self.daemon.kill()
            self.daemon.wait()
        shutil.rmtree(self.dir, ignore_errors=True)

    def start(self):
        log = open(os.path.join(self.dir, "daemon.log"), "a")
        self.daemon = subprocess.Popen([DAEMON, "--port", str(self.port), "--db", self.db, "--threads", "2",
                                        "--checkpoint-seconds", "20", "--speed-probe-seconds", "0"],
                                       stdout=log, stderr=subprocess.STDOUT)
        log.close()
        client = Client("http://127.0.0.1:%d" % self.port)
        for _ in range(200):
            try:
                client.health()
                return client, Peak(self.daemon.pid)
            except Exception:
                time.sleep(0.05)
        self.fail("granulabd did not start")

    def stored_checkpoint(self):
        try:
            with sqlite3.connect(self.db, timeout=10) as db:
                return db.execute("SELECT bytes, chunks, rows FROM checkpoints").fetchone()
        except sqlite3.Error:
            return None

    def test_a_5_million_sphere_job_checkpoints_in_chunks_and_resumes_bit_for_bit(self):
        spec_path = os.path.join(self.dir, "spec.json")
        with open(spec_path, "w") as f:
            json.dump(SPEC, f)
        direct = subprocess.run([CLI, "run", spec_path, "--out", os.path.join(self.dir, "direct"), "--quiet"],
                                capture_output=True, text=True)
        self.assertEqual(direct.returncode, 0, direct.stderr[-2000:])
        with open(os.path.join(self.dir, "direct", "summary.json")) as f:
            summary = json.load(f)
        with open(os.path.join(self.dir, "direct", "curve.csv")) as f:
            direct_curve = f.read()
        spheres, direct_peak = summary["spheres"], summary["peak_rss_bytes"]

        client, peak = self.start()
        job = client.submit(SPEC)
        deadline, stored = time.time() + 1800, None
        while time.time() < deadline and not stored:
            stored = self.stored_checkpoint()
            self.assertNotIn(client.status(job)["status"], ("failed", "cancelled", "succeeded"),
                             "the job ended before its first checkpoint: make it longer")
            time.sleep(1)
        self.assertTrue(stored, "no checkpoint within 30 minutes")
        self.daemon.send_signal(signal.SIGKILL)
        self.daemon.wait()
        first_peak = peak.stop()
        checkpoint_bytes, chunks, rows = stored
        # The state is the grains' poses and the contact candidates with their shear history (about 17 B per
        # sphere early in the confinement, more as contacts form): at this size several 16 MiB chunks, each
        # written and read alone. A 5e7-sphere crystal's, past SQLite's 1 GB blob limit, is written the same way.
        self.assertGreaterEqual(chunks, 4, "a checkpoint of one chunk proves nothing here")
        self.assertGreater(checkpoint_bytes, 3 * 16 * 2**20)

        client, peak = self.start()
        done = client.wait(job, timeout=3600)
        second_peak = peak.stop()
        self.assertEqual(done["status"], "succeeded")
        with sqlite3.connect(self.db, timeout=10) as db:
            resumed = db.execute("SELECT count(*) FROM events WHERE job_id = ? AND kind = 'resumed'", (job,)).fetchone()
        self.assertEqual(resumed[0], 1, "the job started afresh instead of resuming from its checkpoint")
        self.assertEqual(client.curve_csv(job), direct_curve, "the resumed job's curve is not the direct run's")
        worst = max(first_peak, second_peak)
        print(f"\n{spheres} spheres: checkpoint {checkpoint_bytes / 1e9:.2f} GB in {chunks} chunks "
              f"({checkpoint_bytes / spheres:.0f} B/sphere) after {rows} rows; peak memory: direct run "
              f"{direct_peak / 1e9:.2f} GB, daemon {first_peak / 1e9:.2f} GB (writing checkpoints), "
              f"{second_peak / 1e9:.2f} GB (resumed): +{(worst - direct_peak) / direct_peak:.1%}",
              file=sys.stderr)
        # A daemon holds its store, page cache and HTTP threads beside the run; the old way held 3.6x the run.
        self.assertLess(worst, 1.25 * direct_peak + 100e6)


if __name__ == "__main__":
    skip_aware.main()
