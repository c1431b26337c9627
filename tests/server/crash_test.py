#!/usr/bin/python3
"""kill -9 of granulabd with jobs queued and running, then a restart on the same file: every job finishes,
none is lost or duplicated, and the database passes PRAGMA integrity_check (issue 5, crash safety).

Standard library only. The daemon binary comes from $GRANULABD (set by CTest) or build/granulabd.
"""
import os
import random
import signal
import socket
import json
import sqlite3
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "clients", "python"))
from granulab_client import Client  # noqa: E402

DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")
# About 1.5 s of work each at N_e = 4: long enough to be caught running by the kill, and checkpointed.
SPEC = {"experiment": "two_cube_sliding", "grain": {"edge_spheres": 4}, "loading": {"rate_number": 1e-5},
        "output": {"curve_points": 20}}
# 1,333,334 steps, about 2.7 s on this machine's quiet cores: a job must outlive the 1 s checkpoint interval for the
# kill loop to resume one (SPEC's 0.8 s jobs finished between checkpoints on a quiet machine).
LONGER = dict(SPEC, loading={"rate_number": 3e-6})


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class CrashTest(unittest.TestCase):
    def start(self, *extra):
        proc = subprocess.Popen([DAEMON, "--port", str(self.port), "--db", self.db, "--workers", "1", "--threads", "1",
                                 *extra], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.time() + 20
        while time.time() < deadline:
            try:
                self.client.health()
                return proc
            except Exception:
                time.sleep(0.05)
        proc.kill()
        self.fail("granulabd did not start")

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="granulab_crash_")
        self.db = os.path.join(self.dir, "jobs.db")
        self.port = free_port()
        self.client = Client(f"http://127.0.0.1:{self.port}", timeout=10)
        self.proc = None

    def tearDown(self):
        if self.proc and self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            self.proc.wait(timeout=30)

    def test_kill_minus_nine_loses_nothing(self):
        self.proc = self.start()
        ids = [self.client.submit(SPEC) for _ in range(4)]
        deadline = time.time() + 30
        while self.client.status(ids[0])["status"] != "running" and time.time() < deadline:
            time.sleep(0.01)
        self.assertEqual(self.client.status(ids[0])["status"], "running")
        self.proc.send_signal(signal.SIGKILL)
        self.proc.wait(timeout=10)

        self.proc = self.start()  # the same file: the running job is re-queued
        for job_id in ids:
            self.assertEqual(self.client.wait(job_id, timeout=120)["status"], "succeeded")
        jobs = self.client.list(limit=100)
        self.assertEqual(sorted(j["id"] for j in jobs), sorted(ids))  # none lost, none duplicated
        curves = [self.client.curve_csv(i) for i in ids]
        self.assertTrue(all(c == curves[0] for c in curves))  # same spec, same (deterministic) result
        self.proc.send_signal(signal.SIGTERM)
        self.assertEqual(self.proc.wait(timeout=30), 0)
        with sqlite3.connect(self.db) as db:
            self.assertEqual(db.execute("PRAGMA integrity_check").fetchone()[0], "ok")
            kinds = [k for (k,) in db.execute("SELECT kind FROM events")]
        self.assertIn("requeued", kinds)

    def test_sigterm_requeues_the_running_job(self):
        self.proc = self.start()
        job_id = self.client.submit(SPEC)
        deadline = time.time() + 30
        while self.client.status(job_id)["status"] != "running" and time.time() < deadline:
            time.sleep(0.01)
        self.proc.send_signal(signal.SIGTERM)
        self.assertEqual(self.proc.wait(timeout=30), 0)  # stops cleanly, within a progress interval
        with sqlite3.connect(self.db) as db:
            status = db.execute("SELECT status FROM jobs WHERE id = ?", (job_id,)).fetchone()[0]
        self.assertEqual(status, "queued")
        self.proc = self.start()
        self.assertEqual(self.client.wait(job_id, timeout=120)["status"], "succeeded")


    def test_thirty_kills_at_random_moments(self):
        """30 cycles of kill -9 at a random moment with jobs queued and running, restarting on the same
        file each time: every job finishes exactly once, the file is intact, and the curves equal a
        direct run of the same spec (granulab run)."""
        rng = random.Random(20261129)
        ids = []
        kills_while_running = 0
        for cycle in range(30):
            # Checkpoints every second, so kills also land during checkpoint writes and resumed runs.
            self.proc = self.start("--checkpoint-seconds", "1")
            if cycle < 12:
                ids.append(self.client.submit(LONGER))
            time.sleep(rng.uniform(0.0, 1.5))
            if any(j["status"] == "running" for j in self.client.list(limit=100)):
                kills_while_running += 1
            self.proc.send_signal(signal.SIGKILL)
            self.proc.wait(timeout=10)
        self.proc = self.start()
        for job_id in ids:
            self.assertEqual(self.client.wait(job_id, timeout=300)["status"], "succeeded")
        self.assertGreaterEqual(kills_while_running, 10)
        with sqlite3.connect(self.db) as db:
            resumed = db.execute("SELECT count(*) FROM events WHERE kind = 'resumed'").fetchone()[0]
        self.assertGreater(resumed, 0, "no job resumed from a checkpoint")
        self.proc.send_signal(signal.SIGTERM)
        self.assertEqual(self.proc.wait(timeout=30), 0)
        with sqlite3.connect(self.db) as db:
            self.assertEqual(db.execute("PRAGMA integrity_check").fetchone()[0], "ok")
            self.assertEqual(sorted(i for (i,) in db.execute("SELECT id FROM jobs")), sorted(ids))
            for job_id in ids:  # finished exactly once
                (n,) = db.execute("SELECT count(*) FROM events WHERE job_id = ? AND kind = 'succeeded'",
                                  (job_id,)).fetchone()
                self.assertEqual(n, 1, f"job {job_id}")
        self.proc = self.start()
        direct = self.direct_curve(LONGER)
        for job_id in ids:
            self.assertEqual(self.client.curve_csv(job_id), direct, f"job {job_id}")
        print(f"crash loop: 30 kills ({kills_while_running} with a job running, {resumed} resumptions from a "
              f"checkpoint), {len(ids)} jobs, each succeeded once, integrity ok, curves equal a direct run",
              file=sys.stderr)

    def direct_curve(self, spec):
        direct_dir = os.path.join(self.dir, "direct")
        spec_path = os.path.join(self.dir, "direct_spec.json")
        with open(spec_path, "w") as f:
            json.dump(spec, f)
        cli = os.path.join(os.path.dirname(DAEMON), "granulab")
        subprocess.run([cli, "run", spec_path, "--out", direct_dir, "--threads", "1", "--quiet"], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        with open(os.path.join(direct_dir, "curve.csv")) as f:
            return f.read()

    def test_a_long_job_resumes_from_its_checkpoint(self):
        """kill -9 and then SIGTERM in the middle of a ~6 s job with a checkpoint every second: each restart
        resumes it from its last checkpoint (not from zero), and its curve equals a direct run's byte for byte."""
        spec = {"experiment": "two_cube_sliding", "grain": {"edge_spheres": 4}, "loading": {"rate_number": 3e-6},
                "output": {"curve_points": 40}}
        self.proc = self.start("--checkpoint-seconds", "1")
        job = self.client.submit(spec)
        for stop in (signal.SIGKILL, signal.SIGTERM):
            deadline = time.time() + 60
            while time.time() < deadline and self.client.status(job)["progress"] < (0.3 if stop == signal.SIGKILL else 0.6):
                time.sleep(0.05)
            progress = self.client.status(job)["progress"]
            self.proc.send_signal(stop)
            self.proc.wait(timeout=30)
            with sqlite3.connect(self.db) as db:
                (rows,) = db.execute("SELECT rows FROM checkpoints WHERE job_id = ?", (job,)).fetchone()
            self.assertGreater(rows, 0, "no checkpoint was stored")
            if stop == signal.SIGTERM:  # a last checkpoint is taken at the stop itself
                self.assertGreaterEqual(rows, int(progress * 40))
            self.proc = self.start("--checkpoint-seconds", "1")
            # It goes on from the checkpoint: the rows up to it are kept, not recomputed from zero.
            deadline = time.time() + 30
            while self.client.status(job)["status"] != "running" and time.time() < deadline:
                time.sleep(0.02)
            self.assertGreaterEqual(len(self.client.curve(job)["slide_over_size"]), rows)
            print(f"stopped at progress {progress:.2f} by signal {stop}; resumed after {rows} of 41 rows",
                  file=sys.stderr)
        self.assertEqual(self.client.wait(job, timeout=120)["status"], "succeeded")
        self.assertEqual(self.client.curve_csv(job), self.direct_curve(spec))
        with sqlite3.connect(self.db) as db:
            kinds = [k for (k,) in db.execute("SELECT kind FROM events WHERE job_id = ?", (job,))]
            self.assertEqual(kinds.count("resumed"), 2)
            self.assertEqual(db.execute("SELECT count(*) FROM checkpoints").fetchone()[0], 0)  # dropped when done

    # A crystal job whose 101 snapshots of 16 grains are most of what it stores (0.65 MB measured, 0.75 MB
    # expected; a second or two on one thread).
    SNAPSHOT_HEAVY = {"experiment": "crystal_compression", "grain": {"edge_spheres": 3},
                      "crystal": {"grains_x": 2, "rows_z": 4, "layers_y": 2},
                      "loading": {"confining_pressure": 30e3, "max_strain": 0.01, "rate_number": 1e-4},
                      "output": {"curve_points": 50, "snapshot_strains": [k * 0.01 / 100 for k in range(101)]}}

    def test_a_store_refuses_early_what_it_cannot_hold_and_every_accepted_job_fits(self):
        """--max-db-mb 4: submissions are refused with 507 storage_full, naming the room, as soon as the jobs
        queued and running would not fit, not at their first write; every accepted job then succeeds."""
        self.proc = self.start("--max-db-mb", "4", "--max-queued-per-user", "100000")
        accepted, refusal = [], None
        for _ in range(200):
            try:
                accepted.append(self.client.submit(dict(self.SNAPSHOT_HEAVY, label="heavy %d" % len(accepted))))
            except Exception as e:
                refusal = e
                break
        self.assertIsNotNone(refusal, "200 jobs of ~0.7 MB each accepted into a 4 MB store")
        self.assertEqual((getattr(refusal, "status", 0), getattr(refusal, "code", "")), (507, "storage_full"))
        self.assertIn("MB left", str(refusal))
        self.assertGreaterEqual(len(accepted), 2)
        for job in accepted:
            self.assertEqual(self.client.wait(job, timeout=120)["status"], "succeeded", self.client.status(job))
        with sqlite3.connect(self.db) as db:
            self.assertEqual(db.execute("PRAGMA integrity_check").fetchone()[0], "ok")
        print(f"full store: {len(accepted)} jobs accepted and all succeeded, the next refused: {refusal}",
              file=sys.stderr)

    def test_a_store_filled_by_another_program_fails_the_job_with_the_reason_and_nothing_crashes(self):
        """The disk filled behind the daemon's back (here: another connection writing into the same file past
        --max-db-mb): the running job fails with the reason (the reserve file freed so that it can be
        written), is not run again after a restart, further submissions answer 507, the daemon stays up."""
        self.proc = self.start("--max-db-mb", "3", "--max-queued-per-user", "100000")
        self.assertTrue(os.path.exists(self.db + "-reserve"))
        blocker = self.client.submit(dict(SPEC, loading={"rate_number": 2e-6}))  # holds the one worker a few s
        job = self.client.submit(self.SNAPSHOT_HEAVY)
        with sqlite3.connect(self.db) as db:
            db.execute("CREATE TABLE padding (x BLOB)")
            db.execute("INSERT INTO padding VALUES (zeroblob(3200000))")
        try:
            final = self.client.wait(job, timeout=120)
        except Exception:  # wait() raises for a job that did not succeed
            final = self.client.status(job)
        self.assertEqual(final["status"], "failed", final)
        self.assertIn("full", final["error"])
        with self.assertRaises(Exception) as refused:
            self.client.submit(SPEC)
        self.assertEqual(getattr(refused.exception, "status", 0), 507)
        self.assertEqual(self.client.health()["status"], "ok")
        deadline = time.time() + 120  # the blocker may succeed or fail for space too: it only has to end
        while self.client.status(blocker)["status"] in ("queued", "running") and time.time() < deadline:
            time.sleep(0.2)
        self.proc.send_signal(signal.SIGTERM)
        self.assertEqual(self.proc.wait(timeout=30), 0)
        with sqlite3.connect(self.db) as db:
            self.assertEqual(db.execute("PRAGMA integrity_check").fetchone()[0], "ok")
            db.execute("DROP TABLE padding")
        self.proc = self.start()
        time.sleep(1)
        self.assertEqual(self.client.status(job)["status"], "failed")  # not re-queued, not run again
        print(f"filled store: the job failed with '{final['error'][:80]}'", file=sys.stderr)

    def test_one_daemon_per_database_and_per_port(self):
        self.proc = self.start()
        second = subprocess.run([DAEMON, "--port", str(free_port()), "--db", self.db], capture_output=True, text=True,
                                timeout=30)
        self.assertNotEqual(second.returncode, 0)
        self.assertIn("one daemon per database", second.stderr)
        other_db = os.path.join(self.dir, "other.db")
        third = subprocess.run([DAEMON, "--port", str(self.port), "--db", other_db], capture_output=True, text=True,
                               timeout=30)
        self.assertNotEqual(third.returncode, 0)
        self.assertIn("cannot listen", third.stderr)
        self.assertEqual(self.client.health()["status"], "ok")


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import skip_aware  # noqa: E402  (tests/skip_aware.py)


if __name__ == "__main__":
    skip_aware.main()
