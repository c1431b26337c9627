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
import tarfile
import tempfile
import threading
import time
import types
import unittest
import urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "clients", "python"))

from granulab_client import Client, GranulabError, KeyValue, key_values  # noqa: E402

DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")
TINY = {"experiment": "two_cube_sliding", "grain": {"edge_spheres": 3},
        "loading": {"rate_number": 1e-3}, "output": {"curve_points": 10}}
CSV_HEADER = "slide_over_size,normal_over_p0,tangential_over_p0,normal_force,tangential_force"
SLOW = dict(TINY, loading={"rate_number": 1e-8}, output={"curve_points": 1})  # minutes: holds the one worker
# A crystal of 8 grains of 14 spheres: confinement and 1 % of strain in about half a second; snapshots at 0 and 1 %.
CRYSTAL = {"experiment": "crystal_compression", "grain": {"edge_spheres": 2},
           "crystal": {"grains_x": 2, "rows_z": 2, "layers_y": 2},
           "loading": {"max_strain": 0.01, "rate_number": 1e-3}, "output": {"curve_points": 10}}
# Three rows: its front face holds grains spread in x and z whatever rounding does to the confinement (2 x 2 x 2 can
# settle with one grain in front, and a DIC map of a point).
CRYSTAL_FACE = dict(CRYSTAL, crystal={"grains_x": 2, "rows_z": 3, "layers_y": 2})
# Simple-cubic cubes loaded along [0 0 1]: columns of cubes carry the load face to face and never give way within
# 0.05 % strain (about 0.1 s): no first yield and no peak, which the summary says with a reason (issue 51).
LOCKED = {"experiment": "crystal_compression", "label": "sc locked", "grain": {"edge_spheres": 2},
          "crystal": {"lattice": "sc", "grains_x": 2, "layers_y": 2, "rows_z": 3},
          "loading": {"confining_pressure": 30000, "max_strain": 0.0005, "rate_number": 1e-3},
          "output": {"curve_points": 4, "snapshot_strains": []}}
CRYSTAL_COLUMNS = ["strain", "stress_top", "stress_bottom", "deviator", "lateral_strain_x", "lateral_strain_y",
                   "lateral_stress", "kinetic_elastic_ratio", "contacts", "sliding_contacts", "segment",
                   "platen_work", "confinement_work", "elastic_energy", "friction_dissipation", "damping_dissipation",
                   "kinetic_energy", "energy_residual"]
TERMINAL = ("succeeded", "failed", "cancelled")


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
        self.extra = []  # more daemons a test started: (process, log file)
        self.proc = self._spawn(self.port, os.path.join(self.tmp, "test.db"), log=self.log)
        self.client = Client(f"http://127.0.0.1:{self.port}")
        self._await_health(self.proc, self.port, self.log)

    def _spawn(self, port, db, *extra_args, log=None):
        """Starts a granulabd on `port` with its own database; a second daemon logs to its own file."""
        if log is None:
            log = open(os.path.join(self.tmp, f"daemon_{port}.log"), "w+")
        env = dict(os.environ, OMP_WAIT_POLICY="passive")
        proc = subprocess.Popen(
            [DAEMON, "--port", str(port), "--db", db, "--workers", "1", *extra_args],
            stdout=log, stderr=subprocess.STDOUT, env=env)
        if log is not self.log:
            self.extra.append((proc, log))
        return proc

    def _await_health(self, proc, port, log):
        deadline = time.monotonic() + 20
        while True:
            if proc.poll() is not None:
                self.fail(f"granulabd exited with {proc.returncode}:\n{self._log(log)}")
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/v1/health", timeout=2) as r:
                    if r.status == 200:
                        break
            except OSError:
                pass
            if time.monotonic() > deadline:
                self.fail(f"granulabd did not answer /v1/health within 20 s:\n{self._log(log)}")
            time.sleep(0.1)

    @staticmethod
    def _stop(proc):
        if proc.poll() is None:
            proc.send_signal(signal.SIGTERM)
            try:
                proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()

    def tearDown(self):
        self._stop(self.proc)
        for proc, log in self.extra:
            self._stop(proc)
            log.close()
        self.log.close()
        shutil.rmtree(self.tmp, ignore_errors=True)

    def _log(self, log=None):
        log = log or self.log
        log.flush()
        log.seek(0)
        return log.read()[-4000:]

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

    # -- dry runs ----------------------------------------------------------------------------------
    def test_dry_run_answers_the_cost_and_queues_nothing(self):
        before = self.client.list()
        for spec in (TINY, CRYSTAL):
            cost = self.client.dry_run(spec)
            self.assertIs(cost["dry_run"], True)
            self.assertEqual(cost["experiment"], spec["experiment"])
            for key in ("spheres", "grains", "steps", "memory_bytes", "expected_seconds"):
                self.assertGreater(cost[key], 0, key)
            self.assertNotIn("over_budget", cost)  # the default budget holds these
        cost = self.client.dry_run(CRYSTAL)
        self.assertEqual((cost["grains"], cost["spheres"]), (8, 8 * 14))  # rhombic dodecahedra of edge 2
        self.assertEqual(self.client.list(), before)
        self.assertEqual(self.client.health()["queued"], 0)
        # A file path works as for submit().
        path = os.path.join(self.tmp, "crystal.json")
        with open(path, "w") as f:
            json.dump(CRYSTAL, f)
        self.assertEqual(self.client.dry_run(path)["spheres"], cost["spheres"])
        self.assertEqual(self.client.list(), [])

    def test_dry_run_bad_spec_raises_with_field(self):
        with self.assertRaises(GranulabError) as ctx:
            self.client.dry_run(dict(TINY, grain={"edge_spheres": -1}))
        self.assertEqual((ctx.exception.status, ctx.exception.field), (400, "grain.edge_spheres"))
        # Every crystal dimension at its maximum is more spheres than any spec may hold: a bad spec, not a cost.
        huge = dict(CRYSTAL, crystal={"grains_x": 100, "rows_z": 400, "layers_y": 100})
        with self.assertRaises(GranulabError) as ctx:
            self.client.dry_run(huge)
        self.assertEqual((ctx.exception.status, ctx.exception.field), (400, "crystal"))
        self.assertEqual(self.client.list(), [])

    def test_dry_run_over_budget_names_the_limit(self):
        port = free_port()
        proc = self._spawn(port, os.path.join(self.tmp, "small.db"), "--max-sphere-steps", "1e6")
        self._await_health(proc, port, self.extra[-1][1])
        small = Client(f"http://127.0.0.1:{port}")
        cost = small.dry_run(CRYSTAL)  # ~2e7 sphere-steps: still answered 200, with the reason
        self.assertIs(cost["dry_run"], True)
        self.assertGreater(cost["expected_seconds"], 0)
        self.assertIn("max_sphere_steps", cost["over_budget"])
        self.assertNotIn("over_budget", small.dry_run(dict(TINY, loading={"rate_number": 1e-1})))
        with self.assertRaises(GranulabError) as ctx:  # what the dry run announced
            small.submit(CRYSTAL)
        self.assertEqual((ctx.exception.status, ctx.exception.code), (400, "over_budget"))
        self.assertIn("max_sphere_steps", ctx.exception.message)
        self.assertEqual(small.list(), [])

    # -- wait_all ----------------------------------------------------------------------------------
    def test_wait_all_reports_every_outcome(self):
        # One worker runs them in this order; `slow` holds it, so `queued` is still queued when cancelled.
        ok = self.client.submit(TINY)
        failing = self.client.submit(dict(CRYSTAL, crystal={"grains_x": 1, "rows_z": 1, "layers_y": 1}))  # fails
        slow = self.client.submit(SLOW)
        queued = self.client.submit(SLOW)
        self.assertEqual(self.client.status(queued)["status"], "queued")
        self.client.cancel(queued)
        seen = []
        final = self.client.wait_all([ok, failing, queued], timeout=60, poll=0.1, on_progress=seen.append)
        self.assertEqual(set(final), {ok, failing, queued})
        self.assertEqual({i: st["status"] for i, st in final.items()},
                         {ok: "succeeded", failing: "failed", queued: "cancelled"})
        self.assertIn("two grains", final[failing]["error"])
        self.assertTrue(seen)
        for call in seen:
            self.assertIsInstance(call, list)
            self.assertEqual([st["id"] for st in call], [ok, failing, queued])
        self.assertTrue(all(st["status"] in TERMINAL for st in seen[-1]))
        self.assertEqual(self.client.wait_all([], timeout=1), {})
        # `slow` runs for minutes: a short timeout is a TimeoutError, whatever the other jobs did.
        start = time.monotonic()
        with self.assertRaises(TimeoutError):
            self.client.wait_all([ok, slow], timeout=0.5, poll=0.1)
        self.assertLess(time.monotonic() - start, 5)
        self.client.cancel(slow)
        self.assertEqual(self.client.wait_all([slow], timeout=30, poll=0.1)[slow]["status"], "cancelled")

    # -- curves as columns, pandas ---------------------------------------------------------------------
    def _finished(self, spec):
        job = self.client.submit(spec)
        self.assertEqual(self.client.wait(job, timeout=60, poll=0.1)["status"], "succeeded")
        return job

    def test_curve_columns_and_to_pandas(self):
        job = self._finished(CRYSTAL)
        curve = self.client.curve(job)
        self.assertEqual(curve["columns"], CRYSTAL_COLUMNS)
        rows = len(curve["strain"])
        self.assertGreater(rows, 1)
        for name in curve["columns"]:
            self.assertEqual(len(curve[name]), rows, name)
        self.assertAlmostEqual(curve["strain"][-1], 0.01, places=3)

        try:
            import pandas  # noqa: F401
            have_pandas = True
        except ImportError:
            have_pandas = False
        if have_pandas:
            df = self.client.to_pandas(job)
            self.assertEqual(list(df.columns), curve["columns"])
            for name in curve["columns"]:
                self.assertEqual(df[name].tolist(), curve[name], name)
        else:
            with self.assertRaises(ImportError) as ctx:
                self.client.to_pandas(job)
            self.assertIn("python3-pandas", str(ctx.exception))

        # The other path, simulated: no pandas (None in sys.modules fails the import) ...
        saved = sys.modules.get("pandas", None)
        had = "pandas" in sys.modules
        try:
            sys.modules["pandas"] = None
            with self.assertRaises(ImportError) as ctx:
                self.client.to_pandas(job)
            self.assertIn("python3-pandas", str(ctx.exception))
            # ... and a stand-in pandas whose DataFrame keeps the columns it was given.
            fake = types.ModuleType("pandas")
            fake.DataFrame = lambda data: ("DataFrame", data)
            sys.modules["pandas"] = fake
            kind, data = self.client.to_pandas(job)
            self.assertEqual(kind, "DataFrame")
            self.assertEqual(list(data), curve["columns"])
            self.assertEqual(data, {name: curve[name] for name in curve["columns"]})
        finally:
            if had:
                sys.modules["pandas"] = saved
            else:
                sys.modules.pop("pandas", None)

    # -- key values ------------------------------------------------------------------------------------
    def test_key_values_say_none_and_why_for_a_crystal_that_never_yields(self):
        headline = self.client.headline("crystal_compression")
        labels = [v["label"] for v in headline["values"]]
        self.assertIn("first yield", labels)
        locked_sweep, locked = self.client.submit_sweep(LOCKED, {"loading.confining_pressure": [20000, 30000]})
        # CRYSTAL_FACE (about 0.1 s) yields: its curve falls after a first yield near 2.5 p0.
        yielding_sweep, (yielding,) = self.client.submit_sweep(CRYSTAL_FACE, {"material.friction": [0.35]})
        final = self.client.wait_all(locked + [yielding], timeout=60, poll=0.1)
        self.assertEqual({job: st["status"] for job, st in final.items()}, dict.fromkeys(locked + [yielding], "succeeded"))
        items = {j["id"]: j for sweep in (locked_sweep, yielding_sweep) for j in self.client.sweep(sweep)["jobs"]}
        for job in locked:
            summary = final[job]["summary"]
            values = key_values(final[job], headline)
            self.assertEqual([v.label for v in values], labels)
            for v, spec_value in zip(values, headline["values"]):
                group = summary[spec_value["status"]]
                self.assertIs(group["found"], False)
                self.assertEqual(v, KeyValue(spec_value["label"], None, spec_value["unit"], group["reason"]))
                self.assertRegex(v.reason, r"^none to [0-9.]+ % strain")
            # A sweep's item holds the same groups: the same key values.
            self.assertEqual(key_values(items[job], headline), values)
        st = final[yielding]
        first = key_values(st, headline)[labels.index("first yield")]
        self.assertIs(st["summary"]["first_yield"]["found"], True)
        self.assertEqual(first, ("first yield", st["summary"]["first_yield"]["deviator_over_p0"], "p0", None))
        self.assertIsInstance(first.value, float)
        self.assertEqual(key_values(items[yielding], headline), key_values(st, headline))
        # The experiment's whole entry serves as well as its headline; a job without a summary has no values yet.
        entry = {e["name"]: e for e in self.client.experiments()}["crystal_compression"]
        self.assertEqual(key_values(st, entry), key_values(st, headline))
        self.assertEqual(key_values({"id": 1, "status": "queued", "spec": LOCKED}, headline),
                         [(v["label"], None, v["unit"], None) for v in headline["values"]])
        with self.assertRaises(KeyError):
            self.client.headline("no_such_experiment")

    # -- snapshot files and the archive ----------------------------------------------------------------
    def test_snapshot_files_and_archive(self):
        job = self._finished(CRYSTAL_FACE)
        indices = [s["index"] for s in self.client.snapshots(job)]
        self.assertEqual(indices, [0, 1])  # strains 0 and 0.01
        for k in indices:
            dump = self.client.snapshot_file(job, k, "dump").splitlines()
            self.assertEqual(dump[0], "ITEM: TIMESTEP")
            header = next(i for i, line in enumerate(dump) if line.startswith("ITEM: ATOMS"))
            columns = dump[header].split()[2:]
            self.assertEqual(columns[:6], ["id", "type", "x", "y", "z", "radius"])
            atoms = dump[header + 1:]
            self.assertEqual(len(atoms), 12)  # a line per grain
            self.assertTrue(all(len(line.split()) == len(columns) for line in atoms))
            self.assertTrue(all(float(line.split()[5]) > 0 for line in atoms))
            for fmt in ("vtk", "vtk_interfaces", "dic_vtk"):
                self.assertTrue(self.client.snapshot_file(job, k, fmt).startswith("# vtk DataFile"), fmt)
            # The DIC-like map: a finer step gives more nodes; strain 0 is no strain anywhere.
            coarse = self.client.snapshot_file(job, k, "dic_csv", step=0.004).splitlines()
            fine = self.client.snapshot_file(job, k, "dic_csv", step=0.001).splitlines()
            self.assertEqual(coarse[0], "x,z,ux,uy,uz,exx,ezz,exz,gamma_max")
            self.assertGreater(len(fine), 4 * (len(coarse) - 1))
            if k == 0:
                self.assertTrue(all(abs(float(row.split(",")[5])) < 1e-12 for row in fine[1:]
                                    if row.split(",")[5] != "nan"))
            as_json = json.loads(self.client.snapshot_file(job, k, "json"))
            self.assertEqual(as_json, self.client.snapshot(job, k))
            self.assertEqual(self.client.snapshot_file(job, k), "\n".join(dump) + "\n")  # the client's default: dump
        with self.assertRaises(GranulabError) as ctx:
            self.client.snapshot_file(job, 0, "xyz")
        self.assertEqual((ctx.exception.status, ctx.exception.field), (400, "format"))
        with self.assertRaises(GranulabError) as ctx:
            self.client.snapshot_file(job, 7, "dump")
        self.assertEqual(ctx.exception.status, 404)

        path = os.path.join(self.tmp, "job.tar")
        self.assertEqual(self.client.archive(job, path), path)
        self.assertTrue(tarfile.is_tarfile(path))
        with tarfile.open(path) as tar:
            names = set(tar.getnames())
            d = f"job_{job}/"
            expected = {d + "spec.json", d + "summary.json", d + "curve.csv"}
            for k in indices:
                for suffix in (".json", ".dump", "_grains.vtk", "_interfaces.vtk", "_contacts.vtk", "_contacts.dump", "_meshes.vtk", "_dic.csv", "_dic.vtk"):
                    expected.add(f"{d}snapshots/snapshot_{k}{suffix}")
            self.assertLessEqual(expected, names)
            spec = json.loads(tar.extractfile(d + "spec.json").read())
            self.assertEqual(spec, self.client.status(job)["spec"])
            self.assertEqual(spec["crystal"]["grains_x"], CRYSTAL["crystal"]["grains_x"])
            self.assertEqual(tar.extractfile(d + "curve.csv").read().decode(), self.client.curve_csv(job))
            dump = tar.extractfile(f"{d}snapshots/snapshot_1.dump").read().decode()
            self.assertEqual(dump, self.client.snapshot_file(job, 1, "dump"))
            # Every member dated when the job finished, so that two downloads are the same bytes.
            finished = self.client.status(job)["finished_ms"] // 1000
            self.assertEqual({m.mtime for m in tar.getmembers()}, {finished})
        time.sleep(1.1)  # a download dated by the clock would differ now
        again = os.path.join(self.tmp, "job_again.tar")
        self.client.archive(job, again)
        with open(path, "rb") as a, open(again, "rb") as b:
            self.assertEqual(a.read(), b.read(), "two downloads of a finished job's archive differ")
        with self.assertRaises(GranulabError) as ctx:
            self.client.archive(987654, os.path.join(self.tmp, "none.tar"))
        self.assertEqual(ctx.exception.status, 404)

    # -- retries -------------------------------------------------------------------------------------
    def _start_later(self, port, delay):
        """Starts a daemon on `port` after `delay` s in a thread; join the thread before the test ends."""
        def run():
            time.sleep(delay)
            self._spawn(port, os.path.join(self.tmp, f"late_{port}.db"))
        thread = threading.Thread(target=run)
        thread.start()
        return thread

    def test_retries_reach_a_daemon_that_starts_late(self):
        port = free_port()
        thread = self._start_later(port, 1.0)
        try:
            start = time.monotonic()
            with self.assertRaises(GranulabError) as ctx:  # no retries: refused at once
                Client(f"http://127.0.0.1:{port}", retries=0).health()
            self.assertLess(time.monotonic() - start, 0.5)
            self.assertEqual((ctx.exception.status, ctx.exception.code), (0, "unreachable"))
            start = time.monotonic()
            self.assertEqual(Client(f"http://127.0.0.1:{port}", retries=3).health()["status"], "ok")
            self.assertGreaterEqual(time.monotonic() - start, 1.0)  # it was answered by the late daemon
        finally:
            thread.join()

    def test_refused_post_is_retried_once_received(self):
        port = free_port()
        thread = self._start_later(port, 1.0)
        try:
            late = Client(f"http://127.0.0.1:{port}", retries=3)
            job = late.submit(TINY)  # refused twice or so, then received once
        finally:
            thread.join()
        self.assertEqual([j["id"] for j in late.list()], [job])

    def _silent_server(self, answer=b""):
        """A listener that reads each request and closes with `answer` (nothing: no response at all);
        returns (url, list of request lines seen, stop function)."""
        listener = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        listener.bind(("127.0.0.1", 0))
        listener.listen(8)
        listener.settimeout(0.2)
        seen, stop = [], threading.Event()

        def serve():
            while not stop.is_set():
                try:
                    conn, _ = listener.accept()
                except socket.timeout:
                    continue
                with conn:
                    conn.settimeout(5)
                    data = b""
                    while b"\r\n\r\n" not in data:
                        chunk = conn.recv(65536)
                        if not chunk:
                            break
                        data += chunk
                    head, _, body = data.partition(b"\r\n\r\n")
                    length = 0
                    for line in head.split(b"\r\n")[1:]:
                        name, _, value = line.partition(b":")
                        if name.strip().lower() == b"content-length":
                            length = int(value)
                    while len(body) < length:
                        chunk = conn.recv(65536)
                        if not chunk:
                            break
                        body += chunk
                    seen.append(head.split(b"\r\n")[0].decode())
                    if answer:
                        conn.sendall(answer)
            listener.close()

        thread = threading.Thread(target=serve)
        thread.start()

        def halt():
            stop.set()
            thread.join()
        self.addCleanup(halt)
        return f"http://127.0.0.1:{listener.getsockname()[1]}", seen, halt

    def test_only_unanswered_gets_are_retried_not_posts(self):
        url, seen, halt = self._silent_server()
        client = Client(url, retries=2, timeout=5)
        start = time.monotonic()
        with self.assertRaises(GranulabError) as ctx:
            client.health()
        self.assertEqual(ctx.exception.code, "unreachable")
        self.assertGreaterEqual(time.monotonic() - start, 1.4)  # waited 0.5 + 1 s
        self.assertEqual(seen, ["GET /v1/health HTTP/1.1"] * 3)
        del seen[:]
        # The POST was received (the server closed without answering): retrying could run the job twice.
        with self.assertRaises(GranulabError) as ctx:
            client.submit(TINY)
        self.assertEqual(ctx.exception.code, "unreachable")
        self.assertEqual(seen, ["POST /v1/jobs HTTP/1.1"])
        halt()

    def test_503_is_retried_other_errors_are_not(self):
        body = b'{"error":{"code":"too_many_connections","message":"busy"}}'
        busy = (b"HTTP/1.1 503 Service Unavailable\r\nContent-Type: application/json\r\nConnection: close\r\n"
                b"Content-Length: %d\r\n\r\n%s" % (len(body), body))
        url, seen, halt = self._silent_server(busy)
        with self.assertRaises(GranulabError) as ctx:
            Client(url, retries=1).health()
        self.assertEqual((ctx.exception.status, ctx.exception.code), (503, "too_many_connections"))
        self.assertEqual(len(seen), 2)
        halt()
        # A 4xx is an answer: never retried.
        real = Client(f"http://127.0.0.1:{self.port}", retries=3)
        start = time.monotonic()
        with self.assertRaises(GranulabError) as ctx:
            real.status(987654)
        self.assertEqual(ctx.exception.status, 404)
        self.assertLess(time.monotonic() - start, 0.5)

    # -- latest row and warnings in the status ---------------------------------------------------------
    def test_running_job_shows_its_latest_row(self):
        # A compression of 4e5 steps (2-4 s on one thread; 2e5 steps finished too soon to be seen running once small
        # crystals stepped faster): rows are stored every second while it runs.
        job = self.client.submit(dict(CRYSTAL, loading={"max_strain": 0.01, "rate_number": 1.5e-7},
                                      output={"curve_points": 40}, run={"threads": 1}))
        latest_seen, listed = [], []
        deadline = time.monotonic() + 60
        while True:
            st = self.client.status(job)
            if st["status"] in TERMINAL:
                break
            if st["status"] == "running" and "latest" in st:
                latest_seen.append(st["latest"])
                for j in self.client.list(status="running"):
                    if j["id"] == job:  # still running: the rows it had are still there
                        listed.append(j.get("latest"))
            self.assertLess(time.monotonic(), deadline, "job did not finish within 60 s")
            time.sleep(0.1)
        self.assertEqual(st["status"], "succeeded")
        self.assertNotIn("latest", st)
        self.assertNotIn("latest", next(j for j in self.client.list() if j["id"] == job))
        self.assertTrue(latest_seen, "no 'latest' while running")
        for latest in latest_seen:
            self.assertEqual(sorted(latest), sorted(CRYSTAL_COLUMNS))
            self.assertGreaterEqual(latest["strain"], 0)  # the loading's first row is at 0, and may be the latest seen
            self.assertIsInstance(latest["deviator"], float)
        strains = [latest["strain"] for latest in latest_seen]
        self.assertEqual(strains, sorted(strains))
        self.assertGreater(strains[-1], 0)
        self.assertIn(latest_seen[-1]["strain"], self.client.curve(job)["strain"])
        for latest in listed:
            self.assertIsInstance(latest, dict)
            self.assertIn("strain", latest)

    def test_warnings_in_status_and_list(self):
        # Two grains, one per {111} layer, do not touch each other: with no elastic energy the kinetic
        # criterion never holds and the confinement stops at its step limit (200000 steps, ~2 s on one thread).
        # A sample not at rest is not loaded: the job fails, saying what the confinement reached (issue 51). In the
        # taut bag: the wrapped one (the default) presses the two together, and they settle.
        unsettled = dict(CRYSTAL, crystal={"grains_x": 1, "rows_z": 1, "layers_y": 2},
                         loading=dict(CRYSTAL.get("loading", {}), confinement="taut_membrane"),
                         run={"threads": 1, "skin_factor": 0.5})
        failed = self.client.submit(unsettled)
        warned = self.client.submit(CRYSTAL)  # R = 1e-3, 50 p0/E: the rate's warning
        quiet = self.client.submit(TINY)
        final = self.client.wait_all([failed, warned, quiet], timeout=60, poll=0.2)
        self.assertEqual(final[failed]["status"], "failed")
        error = self.client.status(failed)["error"]
        self.assertIn("confinement failed", error)
        self.assertIn("kPa against p0 = 60 kPa", error)
        self.assertEqual(final[warned]["status"], "succeeded")
        st = self.client.status(warned)
        self.assertTrue(any("50 x p0/E" in w for w in st["warnings"]), st["warnings"])
        self.assertEqual(st["warnings"], st["summary"]["warnings"])
        self.assertTrue(st["summary"]["confinement"]["converged"])
        listed = {j["id"]: j for j in self.client.list()}
        self.assertEqual(listed[warned]["warnings"], st["warnings"])
        self.assertNotIn("warnings", listed[quiet])  # no warnings: no key
        self.assertNotIn("warnings", self.client.status(quiet))

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

    def test_ctrl_c_on_wait_stops_waiting_not_the_job(self):
        script = os.path.join(ROOT, "clients", "python", "granulab_client.py")
        job = self.client.submit(SLOW)
        proc = subprocess.Popen([sys.executable, script, "--server", f"http://127.0.0.1:{self.port}", "wait", str(job)],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        time.sleep(1.0)  # waiting by now
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=30)
        self.assertEqual(proc.returncode, 130, err)
        self.assertIn(f"stopped waiting; job {job} goes on", err)
        self.assertNotIn("Traceback", err)
        self.assertIn(self.client.status(job)["status"], ("queued", "running"))  # not cancelled
        self.client.cancel(job)


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import skip_aware  # noqa: E402  (tests/skip_aware.py)


if __name__ == "__main__":
    skip_aware.main()
