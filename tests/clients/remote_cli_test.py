#!/usr/bin/python3
"""The CLI's server commands as a shared server's users run them (issue 25, point 8), against a real granulabd
on loopback with a real SQLite file and tokens:

- `status`, `cancel`, `delete`, `priority` and `list` print lines for people, `--json` the server's answer;
- `list` shows each job's owner;
- `--server URL/` with a trailing slash reaches the server;
- `submit -` reads the spec from standard input;
- `results` of an unknown job writes nothing, not even its folder;
- `wait` into a log (not a terminal) writes a line as each job's progress passes another tenth, each line
  there as soon as it is written;
- `sweep` writes sweep.csv with each column once, also where a key value's place on the curve is another key
  value (issue 51);
- `sweep --vary 'loading.axis=[0,0,1],[1,0,0]'` varies an array field: two jobs, each stored with its axis, and
  sweep.csv has each axis in one cell; the Python client's dict of lists does the same; a malformed --vary exits 2
  with what is wrong and the syntax, before anything is sent, and a value the spec refuses exits 1 naming the field
  (issue 51, part 4);
- `make run`'s demo script exits 0 when Ctrl-C or a TERM stops it, with the daemon stopped (issue 51).

Run from the repository root:  /usr/bin/python3 tests/clients/remote_cli_test.py
Standard library only; the binaries come from $GRANULABD (set by CTest) or build/.
"""
import csv
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "clients", "python"))
import skip_aware  # noqa: E402
from granulab_client import Client  # noqa: E402

DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")
CLI = os.path.join(os.path.dirname(DAEMON), "granulab")
TINY = {"experiment": "two_cube_sliding", "grain": {"edge_spheres": 2}, "loading": {"rate_number": 0.1},
        "output": {"curve_points": 4}, "label": "tiny"}
# 4,000,000 steps, about 8 s on one of this machine's quiet cores (2e-6 s a step): long enough for a log to show its
# progress (half of it, 4 s, printed two running lines).
SLOWER = {"experiment": "two_cube_sliding", "grain": {"edge_spheres": 4}, "loading": {"rate_number": 1e-6},
          "output": {"curve_points": 20}, "label": "slower"}
# A crystal pulled apart (about a second): its headline's tensile strength lies at the failure strain, itself a key
# value, and its y is the strength again.
TENSION = {"experiment": "crystal_tension", "grain": {"edge_spheres": 2},
           "crystal": {"lattice": "sc", "grains_x": 2, "rows_z": 5, "layers_y": 1},
           "loading": {"rate_number": 0.1, "max_strain": 0.001}, "output": {"curve_points": 4}, "label": "tension"}

# A simple cubic crystal of 12 cubes of 8 spheres to 0.05 % strain: about 0.1 s a job, along any cube axis.
SC = {"experiment": "crystal_compression", "label": "sc axes", "grain": {"edge_spheres": 2},
      "crystal": {"lattice": "sc", "grains_x": 2, "layers_y": 2, "rows_z": 3},
      "loading": {"confining_pressure": 30000, "max_strain": 0.0005, "rate_number": 1e-3},
      "output": {"curve_points": 4, "snapshot_strains": []}}


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class RemoteCliTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="granulab_cli_")
        tokens = os.path.join(cls.dir, "tokens")
        made = subprocess.run([DAEMON, "token", "add", "alice", "--token-file", tokens], capture_output=True,
                              text=True, check=True)
        cls.token = made.stdout.strip()
        cls.port = free_port()
        cls.server = "http://127.0.0.1:%d" % cls.port
        cls.log = open(os.path.join(cls.dir, "daemon.log"), "w")
        cls.daemon = subprocess.Popen([DAEMON, "--port", str(cls.port), "--db", os.path.join(cls.dir, "g.db"),
                                       "--workers", "1", "--threads", "1", "--token-file", tokens,
                                       "--speed-probe-seconds", "0"], stdout=cls.log, stderr=subprocess.STDOUT)
        for _ in range(200):
            if cls.cli("list").returncode == 0:
                break
            time.sleep(0.05)

    @classmethod
    def tearDownClass(cls):
        cls.daemon.terminate()
        cls.daemon.wait(timeout=30)
        cls.log.close()
        shutil.rmtree(cls.dir, ignore_errors=True)

    @classmethod
    def cli(cls, *args, server=None, stdin=None, stderr_file=None):
        env = dict(os.environ, GRANULAB_SERVER=server or cls.server, GRANULAB_TOKEN=cls.token)
        return subprocess.run([CLI] + list(args), env=env, input=stdin, text=True, capture_output=stderr_file is None,
                              stdout=subprocess.PIPE if stderr_file else None, stderr=stderr_file, timeout=120)

    def submit(self, spec):
        path = os.path.join(self.dir, "spec-%d.json" % time.monotonic_ns())
        with open(path, "w") as f:
            json.dump(spec, f)
        made = self.cli("submit", path)
        self.assertEqual(made.returncode, 0, made.stderr)
        return made.stdout.strip()

    def test_status_cancel_delete_and_list_print_lines_for_people_and_json_for_scripts(self):
        job = self.submit(TINY)
        self.assertEqual(self.cli("wait", job).returncode, 0)
        status = self.cli("status", job)
        self.assertEqual(status.returncode, 0, status.stderr)
        self.assertTrue(status.stdout.startswith("job %s  succeeded  100.0 %%  two_cube_sliding  tiny" % job),
                        status.stdout)
        self.assertIn("owner: alice", status.stdout)
        self.assertIn(" steps in ", status.stdout)
        self.assertEqual(json.loads(self.cli("status", job, "--json").stdout)["status"], "succeeded")
        listed = self.cli("list").stdout
        line = next(l for l in listed.splitlines() if l.split()[0] == job)
        self.assertIn(" alice ", line)
        self.assertIn("tiny", line)
        self.assertEqual(json.loads(self.cli("list", "--json").stdout)["jobs"][0]["owner"], "alice")
        priority = self.cli("priority", job, "--priority", "-5")
        self.assertNotEqual(priority.returncode, 0)  # a finished job has no priority to change: the server says so
        self.assertIn("HTTP 409", priority.stderr)
        queued = self.submit(SLOWER)
        cancelled = self.cli("cancel", queued)
        self.assertEqual(cancelled.returncode, 0, cancelled.stderr)
        self.assertRegex(cancelled.stdout, r"^job %s: (cancelled|running)\n$" % queued)
        self.assertEqual(self.cli("delete", job).stdout, "job %s deleted\n" % job)
        self.assertNotEqual(self.cli("status", job).returncode, 0)

    def test_a_trailing_slash_reaches_the_server(self):
        listed = self.cli("list", server=self.server + "/")
        self.assertEqual(listed.returncode, 0, listed.stderr)

    def test_submit_dash_reads_the_spec_from_standard_input(self):
        made = self.cli("submit", "-", stdin=json.dumps(TINY))
        self.assertEqual(made.returncode, 0, made.stderr)
        self.assertRegex(made.stdout, r"^\d+\n$")
        dry = self.cli("submit", "-", "--dry-run", stdin=json.dumps(TINY))
        self.assertIn("two_cube_sliding", dry.stdout)

    def test_results_of_an_unknown_job_leave_no_folder(self):
        out = os.path.join(self.dir, "results-999")
        made = self.cli("results", "999999", "--out", out)
        self.assertNotEqual(made.returncode, 0)
        self.assertIn("HTTP 404", made.stderr)
        self.assertFalse(os.path.exists(out))

    def test_wait_into_a_log_shows_progress_as_it_goes(self):
        job = self.submit(SLOWER)
        log_path = os.path.join(self.dir, "wait.log")
        with open(log_path, "w") as log:
            env = dict(os.environ, GRANULAB_SERVER=self.server, GRANULAB_TOKEN=self.token)
            waiter = subprocess.Popen([CLI, "wait", job], env=env, stdout=log, stderr=log)
            seen_running = False
            while waiter.poll() is None:
                with open(log_path) as f:
                    # A line of the running job is in the file while the job still runs.
                    if "running" in f.read() and waiter.poll() is None:
                        seen_running = True
                time.sleep(0.1)
        with open(log_path) as f:
            lines = [l for l in f.read().splitlines() if l.startswith("job %s" % job)]
        self.assertEqual(waiter.returncode, 0)
        self.assertTrue(seen_running, lines)
        running = [l for l in lines if " running " in l]
        self.assertGreaterEqual(len(running), 3, lines)  # several tenths of progress, not one line per status

    def test_sweep_csv_names_each_column_once(self):
        path = os.path.join(self.dir, "tension.json")
        with open(path, "w") as f:
            json.dump(TENSION, f)
        out = os.path.join(self.dir, "tension-sweep")
        made = self.cli("sweep", path, "--vary", "loading.max_strain=0.001,0.002", "--out", out)
        self.assertEqual(made.returncode, 0, made.stderr)
        with open(os.path.join(out, "sweep.csv")) as f:
            rows = [line.split(",") for line in f.read().splitlines()]
        header = rows[0]
        self.assertEqual(len(header), len(set(header)), header)
        self.assertEqual(header[:3], ["id", "loading.max_strain", "status"])
        self.assertIn("tensile_strength", header)
        self.assertIn("failure_strain", header)
        self.assertEqual(len(rows), 3)
        for row in rows[1:]:
            self.assertEqual(len(row), len(header), row)
            self.assertEqual(row[2], "succeeded", row)

    def test_sweep_varies_an_array_field(self):
        path = os.path.join(self.dir, "sc.json")
        with open(path, "w") as f:
            json.dump(SC, f)
        out = os.path.join(self.dir, "axis-sweep")
        made = self.cli("sweep", path, "--vary", "loading.axis=[0,0,1],[1,0,0]", "--out", out)
        self.assertEqual(made.returncode, 0, made.stderr)
        with open(os.path.join(out, "sweep.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 2, rows)
        axes = []
        for row in rows:
            self.assertEqual(row["status"], "succeeded", row)
            job = json.loads(self.cli("status", row["id"], "--json").stdout)
            self.assertEqual(job["status"], "succeeded")
            self.assertEqual(job["spec"]["loading"]["axis"], json.loads(row["loading.axis"]))
            self.assertEqual(job["sweep_values"], {"loading.axis": job["spec"]["loading"]["axis"]})
            self.assertEqual(job["summary"]["spec"]["loading"]["axis"], job["spec"]["loading"]["axis"])
            axes.append(job["spec"]["loading"]["axis"])
        self.assertEqual(sorted(axes), [[0, 0, 1], [1, 0, 0]])

        # The Python client's dict of lists: a list per point (checked as stored, then cancelled).
        client = Client(self.server, token=self.token)
        sweep, jobs = client.submit_sweep(SC, {"loading.axis": [[0, 1, 0], [1, 0, 0]]}, mode="zip")
        client.cancel_sweep(sweep)
        self.assertEqual([client.status(j)["spec"]["loading"]["axis"] for j in jobs], [[0, 1, 0], [1, 0, 0]])

        # Malformed: exit 2, what is wrong and the syntax, nothing sent (no folder, no sweep).
        before = len(client.sweeps())
        for option, what in [("loading.axis=[1,1,0],[1,1,1", "a '[' is never closed"),
                             ("loading.axis", "no '=' between the field and its values"),
                             ("loading.axis=[1,1,0],,[1,1,1]", "value 2 of 3 is empty")]:
            bad = os.path.join(self.dir, "bad-sweep")
            made = self.cli("sweep", path, "--vary", option, "--out", bad)
            self.assertEqual(made.returncode, 2, made.stderr)
            self.assertIn("--vary '%s': %s" % (option, what), made.stderr)
            self.assertIn("--vary 'loading.axis=[1,1,0],[1,1,1]'", made.stderr)
            self.assertFalse(os.path.exists(bad))
        made = self.cli("sweep", path, "--zip", "--vary", "loading.axis=[0,0,1],[1,0,0]", "--vary",
                        "crystal.lattice=sc", "--out", bad)
        self.assertEqual(made.returncode, 2, made.stderr)
        self.assertIn("'crystal.lattice' has 1", made.stderr)
        self.assertEqual(len(client.sweeps()), before)
        # A value the spec refuses: the server's 400 names the field and the value.
        made = self.cli("sweep", path, "--vary", "loading.axis=[0,0,1],[13,0,0]", "--out", bad)
        self.assertEqual(made.returncode, 1, made.stderr)
        self.assertIn("HTTP 400: 'vary.loading.axis' value [13,0,0]", made.stderr)

    def test_a_crystal_that_never_yields_has_no_first_yield(self):
        # Cubes stacked along [0 0 1] have no plane to slide on: the deviator rises to the end (issue 51). No number
        # may pass for a first yield or a peak: the summary, the sweep's JSON, sweep.csv and the watch line say none.
        path = os.path.join(self.dir, "sc-locked.json")
        with open(path, "w") as f:
            json.dump(SC, f)
        out = os.path.join(self.dir, "locked-sweep")
        made = self.cli("sweep", path, "--vary", "loading.confining_pressure=30000,40000", "--out", out)
        self.assertEqual(made.returncode, 0, made.stderr)
        self.assertRegex(made.stderr, r"first yield: none to 0\.05\d? % strain \(no drop after its largest, \d+\.?\d* p0\)")
        with open(os.path.join(out, "sweep.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 2, rows)
        for row in rows:
            self.assertEqual(row["status"], "succeeded", row)
            for group in ("first_yield", "peak"):
                self.assertEqual(row[group + "_found"], "false", row)
                self.assertTrue(row[group + "_reason"].startswith("none to 0.05"), row)
                self.assertEqual(row[group + "_deviator_over_p0"], "", row)
                self.assertEqual(row[group + "_strain"], "", row)
            job = json.loads(self.cli("status", row["id"], "--json").stdout)
            summary = job["summary"]
            self.assertEqual(set(summary["first_yield"]), {"found", "reason"}, summary["first_yield"])
            self.assertFalse(summary["peak"]["found"])
            self.assertGreater(summary["apparent_modulus"]["affine_axial"], 0)
        client = Client(self.server, token=self.token)
        sweep = re.search(r"sweep (\d+): 2 jobs", made.stderr).group(1)
        for item in client.sweep(sweep)["jobs"]:
            self.assertEqual(item["first_yield"]["found"], False, item)
            self.assertNotIn("deviator_over_p0", item["first_yield"])


class DemoScriptTest(unittest.TestCase):
    """`make run`'s clients/demo.sh: Ctrl-C or a TERM (here to its whole process group, as a terminal sends it, while
    it waits on the demo's job) stops the daemon and exits 0, so make reports no error (issue 51)."""

    def test_a_signal_stops_the_daemon_and_the_script_exits_zero(self):
        for sig in (signal.SIGINT, signal.SIGTERM):
            with self.subTest(signal=sig.name), tempfile.TemporaryDirectory(prefix="granulab_demo_") as folder:
                port = free_port()
                env = dict(os.environ, BUILD=os.path.dirname(DAEMON), PORT=str(port),
                           DB=os.path.join(folder, "demo.db"))
                env.pop("GRANULAB_TOKEN", None)
                demo = subprocess.Popen([os.path.join(ROOT, "clients", "demo.sh")], cwd=ROOT, env=env,
                                        start_new_session=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                        text=True)
                seen = ""
                while not re.search(r"^job \d+$", seen, re.M) and demo.poll() is None:
                    seen += demo.stdout.readline()
                os.killpg(demo.pid, sig)
                out = seen + demo.communicate(timeout=60)[0]
                self.assertEqual(demo.returncode, 0, out)
                self.assertIn("granulabd stopped", out)
                with socket.socket() as s:  # nobody serves the port any more
                    self.assertNotEqual(s.connect_ex(("127.0.0.1", port)), 0, out)


if __name__ == "__main__":
    skip_aware.main()
