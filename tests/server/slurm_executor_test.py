#!/usr/bin/python3
"""granulabd --executor slurm against a real one-node Slurm cluster on loopback (issue 13).

Installs Debian's slurm-wlm, munge, slurmrestd and slurm-wlm-jwt-plugin when missing (as root; a busy dpkg
lock is waited for), starts munged, slurmctld, slurmd and slurmrestd under a temp dir on free ports, then
granulabd with --executor slurm, and checks:
- a sweep's three jobs run as one Slurm job array and their curves equal `granulab run` of the same specs;
- a cancel through the API reaches Slurm (the Slurm job ends CANCELLED);
- a job longer than its Slurm time limit is warned (USR1), checkpoints, is requeued as a new Slurm job,
  resumes and finishes with the curve of an uninterrupted local run;
- granulabd stopped and started again while jobs run on the cluster (one of them ending meanwhile) neither
  loses nor repeats them;
- a Slurm job that fails (a broken worker, exit 3) fails its job with Slurm's state and exit code; the daemon
  here authenticates with a token in SLURM_JWT instead of the key;
- with --tls-cert, the workers reach the daemon over HTTPS, trusting its self-signed certificate.
Everything it started is stopped by PID. Standard library only.
"""
import csv
import io
import json
import os
import secrets
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
sys.path.insert(0, os.path.join(ROOT, "clients", "python"))
from granulab_client import Client  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from debian_packages import install_missing  # noqa: E402  (tests/debian_packages.py)

DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")
CLI = os.path.join(os.path.dirname(DAEMON), "granulab")
PACKAGES = ["slurm-wlm", "munge", "slurmrestd", "slurm-wlm-jwt-plugin"]

# Two cubes at N_e = 4 on one thread: 0.6 s at rate 1e-5, 9 s at 6e-7.
def short_spec(rate):
    return {"experiment": "two_cube_sliding", "grain": {"edge_spheres": 4},
            "loading": {"rate_number": rate, "max_slide": 0.3}, "output": {"curve_points": 30}}

# About 60 s on one thread (6.7 million steps): with the 1-minute Slurm time limit the daemon sets here, Slurm's
# warning (30 s before the limit, checked every ~30 s) came 20-30 s into each Slurm job, so even a machine
# twice as fast is warned at least once.
LONG_SPEC = {"experiment": "two_cube_sliding", "grain": {"edge_spheres": 10},
             "loading": {"rate_number": 3e-7, "max_slide": 0.4}, "output": {"curve_points": 40}}


_HANDED_OUT = set()


def free_port():
    """A port free now and not handed out before in this run: two quick bind(0)s may return the same port, and then
    slurmctld and slurmd both try it ("Error binding slurm stream socket: Address already in use", seen once)."""
    while True:
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        if port not in _HANDED_OUT:
            _HANDED_OUT.add(port)
            return port


def pid_alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split(")")[-1].split()[0] != "Z"  # a zombie is gone
    except OSError:
        return False


def stop_pid(pid, timeout=20):
    if not pid or not pid_alive(pid):
        return
    try:
        os.kill(pid, signal.SIGTERM)
    except ProcessLookupError:
        return
    deadline = time.time() + timeout
    while time.time() < deadline and pid_alive(pid):
        time.sleep(0.1)
    if pid_alive(pid):
        os.kill(pid, signal.SIGKILL)


class Cluster:
    """munged, slurmctld, slurmd and slurmrestd under `root`, on free loopback ports."""

    def __init__(self, root):
        self.root = root
        self.pids = {}
        self.restd = None
        self.rest_port = free_port()
        self.conf = os.path.join(root, "slurm.conf")
        self.jwt_key = os.path.join(root, "jwt.key")
        self.jobcomp = os.path.join(root, "jobcomp.txt")

    def path(self, *parts):
        return os.path.join(self.root, *parts)

    def start(self):
        for d in ["munge_key", "munge_sock", "state", "spool/localhost", "log", "run"]:
            os.makedirs(self.path(d), exist_ok=True)
        os.chmod(self.path("munge_key"), 0o700)
        os.chmod(self.path("munge_sock"), 0o755)
        key = self.path("munge_key", "munge.key")
        subprocess.run(["mungekey", "--create", f"--keyfile={key}"], check=True)
        self.socket = self.path("munge_sock", "munge.socket")
        subprocess.run(["munged", f"--key-file={key}", f"--socket={self.socket}",
                        f"--pid-file={self.path('run', 'munged.pid')}", f"--seed-file={self.path('run', 'munge.seed')}",
                        f"--log-file={self.path('log', 'munged.log')}"], check=True)
        self.pids["munged"] = self.read_pid("munged.pid")
        with open(self.jwt_key, "wb") as f:
            f.write(secrets.token_bytes(32))
        os.chmod(self.jwt_key, 0o600)
        node = subprocess.run(["slurmd", "-C"], capture_output=True, text=True, check=True).stdout.splitlines()[0]
        node_fields = [f for f in node.split() if not f.startswith(("NodeName=", "RealMemory="))]
        conf = f"""ClusterName=granulabtest
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort={free_port()}
SlurmdPort={free_port()}
SlurmUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={self.socket}
AuthAltTypes=auth/jwt
AuthAltParameters=jwt_key={self.jwt_key}
StateSaveLocation={self.path('state')}
SlurmdSpoolDir={self.path('spool')}
SlurmctldPidFile={self.path('run', 'slurmctld.pid')}
SlurmdPidFile={self.path('run', 'slurmd.pid')}
SlurmctldLogFile={self.path('log', 'slurmctld.log')}
SlurmdLogFile={self.path('log', 'slurmd.log')}
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
EnforcePartLimits=ALL
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc={self.jobcomp}
MinJobAge=3600
MailProg=/bin/true
ReturnToService=2
NodeName=localhost NodeHostname=localhost NodeAddr=127.0.0.1 RealMemory=1000 {' '.join(node_fields)}
PartitionName=main Nodes=localhost Default=YES MaxTime=INFINITE State=UP
"""
        with open(self.conf, "w") as f:
            f.write(conf)
        subprocess.run(["slurmctld", "-f", self.conf], check=True)
        self.pids["slurmctld"] = self.read_pid("slurmctld.pid")
        subprocess.run(["slurmd", "-f", self.conf, "-N", "localhost"], check=True)
        self.pids["slurmd"] = self.read_pid("slurmd.pid")
        env = dict(os.environ, SLURM_JWT="daemon", SLURM_CONF=self.conf)
        self.restd = subprocess.Popen(["slurmrestd", "-f", self.conf, "-u", "nobody", "-a", "rest_auth/jwt", "-s",
                                       "openapi/v0.0.38", f"127.0.0.1:{self.rest_port}"], env=env,
                                      stdout=open(self.path("log", "slurmrestd.log"), "w"), stderr=subprocess.STDOUT)
        self.pids["slurmrestd"] = self.restd.pid
        deadline = time.time() + 60
        while time.time() < deadline:
            r = subprocess.run(["sinfo", "-h", "-o", "%T"], capture_output=True, text=True,
                               env=dict(os.environ, SLURM_CONF=self.conf))
            if r.stdout.strip() == "idle" and self.rest_answers():
                return
            time.sleep(0.3)
        raise RuntimeError("the Slurm cluster did not come up: " + self.logs())

    def rest_answers(self):
        try:
            with socket.create_connection(("127.0.0.1", self.rest_port), timeout=1):
                return True
        except OSError:
            return False

    def read_pid(self, name):
        path = self.path("run", name)
        for _ in range(100):
            if os.path.exists(path):
                with open(path) as f:
                    text = f.read().strip()
                if text:
                    return int(text)
            time.sleep(0.1)
        raise RuntimeError(f"no pid file {path}")

    def squeue(self):
        r = subprocess.run(["squeue", "-h", "-o", "%i %T"], capture_output=True, text=True,
                           env=dict(os.environ, SLURM_CONF=self.conf))
        return r.stdout.strip()

    def completed(self):
        """The jobcomp file: one {JobId, Name, JobState, ...} per finished Slurm job."""
        if not os.path.exists(self.jobcomp):
            return []
        out = []
        with open(self.jobcomp) as f:
            for line in f:
                out.append(dict(kv.split("=", 1) for kv in line.split() if "=" in kv))
        return out

    def logs(self):
        text = ""
        for name in ["slurmctld.log", "slurmd.log", "slurmrestd.log"]:
            p = self.path("log", name)
            if os.path.exists(p):
                with open(p, errors="replace") as f:
                    text += f"\n--- {name}\n" + "".join(f.readlines()[-15:])
        return text

    def stop(self):
        env = dict(os.environ, SLURM_CONF=self.conf)
        if pid_alive(self.pids.get("slurmctld", 0)):
            subprocess.run(["scancel", "--full", "-u", "root"], env=env, capture_output=True)
            deadline = time.time() + 30
            while time.time() < deadline and self.squeue():
                time.sleep(0.3)
        for name in ["slurmrestd", "slurmd", "slurmctld", "munged"]:
            stop_pid(self.pids.get(name))
        if self.restd:
            self.restd.wait(timeout=10)


class SlurmExecutorTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        install_missing(PACKAGES, "Slurm")
        cls.dir = tempfile.mkdtemp(prefix="granulab_slurm_")
        os.chmod(cls.dir, 0o755)  # munged wants its socket's folders searchable by all
        cls.cluster = Cluster(os.path.join(cls.dir, "cluster"))
        os.makedirs(cls.cluster.root)
        try:
            cls.cluster.start()
        except Exception:
            cls.cluster.stop()
            raise
        cls.port = free_port()
        cls.db = os.path.join(cls.dir, "jobs.db")
        cls.daemon = None
        cls.client = Client(f"http://127.0.0.1:{cls.port}", timeout=20)
        cls.start_daemon()

    @classmethod
    def tearDownClass(cls):
        cls.stop_daemon()
        cls.cluster.stop()
        if not os.environ.get("GRANULAB_KEEP_TEST_DIR"):
            shutil.rmtree(cls.dir, ignore_errors=True)

    @classmethod
    def start_daemon(cls, time_limit=1, extra=(), jwt=None, client=None):
        """granulabd on the cluster; `time_limit`: --slurm-time-limit (min), the Slurm jobs' limit here.
        `jwt`: a token in SLURM_JWT instead of the key file; `client`: the one that asks for its health (an
        https one for a daemon with --tls-cert)."""
        client = client or cls.client
        log = open(os.path.join(cls.dir, "granulabd.log"), "a")
        env = dict(os.environ, SLURM_CONF=cls.cluster.conf)
        auth = ["--slurm-jwt-key", cls.cluster.jwt_key]
        if jwt:
            env["SLURM_JWT"], auth = jwt, []
        cls.daemon = subprocess.Popen(
            [DAEMON, "--port", str(cls.port), "--db", cls.db, "--threads", "1", "--checkpoint-seconds", "3",
             "--executor", "slurm", "--slurm-url", f"http://127.0.0.1:{cls.cluster.rest_port}", "--slurm-user", "root",
             *auth, "--slurm-time-limit", str(time_limit), "--slurm-signal-seconds", "30",
             "--slurm-output", os.path.join(cls.dir, "slurm-%j.out"), *extra],
            stdout=log, stderr=subprocess.STDOUT, env=env)
        log.close()  # the daemon has its own descriptor
        deadline = time.time() + 30
        while time.time() < deadline:
            if cls.daemon.poll() is not None:
                raise RuntimeError("granulabd exited: " + cls.daemon_log())
            try:
                if client.health().get("executor") == "slurm":
                    return
            except Exception:
                time.sleep(0.1)
        raise RuntimeError("granulabd did not start: " + cls.daemon_log())

    @classmethod
    def stop_daemon(cls):
        if cls.daemon and cls.daemon.poll() is None:
            cls.daemon.send_signal(signal.SIGTERM)
            cls.daemon.wait(timeout=30)
        cls.daemon = None

    @classmethod
    def daemon_log(cls):
        """The daemon's last lines, and the Slurm jobs' output (the workers' logs)."""
        with open(os.path.join(cls.dir, "granulabd.log"), errors="replace") as f:
            text = "".join(f.readlines()[-30:])
        for name in sorted(os.listdir(cls.dir)):
            if name.startswith("slurm-") and name.endswith(".out"):
                with open(os.path.join(cls.dir, name), errors="replace") as f:
                    text += f"\n--- {name}\n" + "".join(f.readlines()[-10:])
        return text

    def local_curve(self, spec, name):
        path = os.path.join(self.dir, name + ".json")
        with open(path, "w") as f:
            json.dump(spec, f)
        out = os.path.join(self.dir, name)
        subprocess.run([CLI, "run", path, "--out", out, "--threads", "1", "--quiet"], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        with open(os.path.join(out, "curve.csv")) as f:
            return f.read()

    def wait_for(self, job_id, statuses, timeout):
        deadline = time.time() + timeout
        while time.time() < deadline:
            job = self.client.status(job_id)
            if job["status"] in statuses:
                return job
            time.sleep(0.3)
        self.fail(f"job {job_id} not {statuses} within {timeout} s: {self.client.status(job_id)}\n"
                  f"{self.daemon_log()}{self.cluster.logs()}")

    def test_1_sweep_runs_as_a_job_array_with_local_curves(self):
        _, jobs = self.client.submit_sweep(short_spec(1e-5), {"loading.rate_number": [1e-5, 2e-5, 4e-5]})
        done = [self.wait_for(j, {"succeeded", "failed", "cancelled"}, 120) for j in jobs]
        for job in done:
            self.assertEqual(job["status"], "succeeded", f"{job}\n{self.daemon_log()}")
        arrays = {job["slurm_job_id"].split("_")[0] for job in done}
        self.assertEqual(len(arrays), 1, f"one array for the sweep: {[j['slurm_job_id'] for j in done]}")
        self.assertEqual(sorted(job["slurm_job_id"].split("_")[1] for job in done), ["0", "1", "2"])
        for job, rate in zip(done, [1e-5, 2e-5, 4e-5]):
            self.assertEqual(self.client.curve_csv(job["id"]), self.local_curve(short_spec(rate), f"local_{rate}"),
                             f"job {job['id']} (Slurm {job['slurm_job_id']}) against a local run")

    def test_2_cancel_reaches_slurm(self):
        job_id = self.client.submit(LONG_SPEC)
        job = self.wait_for(job_id, {"running"}, 60)
        slurm_id = job["slurm_job_id"]
        self.client.cancel(job_id)
        self.wait_for(job_id, {"cancelled"}, 60)
        deadline = time.time() + 60
        while time.time() < deadline:
            ended = [c for c in self.cluster.completed() if c.get("JobId") == slurm_id]
            if ended:
                self.assertEqual(ended[0].get("JobState"), "CANCELLED", ended[0])
                return
            time.sleep(0.3)
        self.fail(f"Slurm job {slurm_id} did not end: {self.cluster.squeue()}")

    def test_3_time_limit_requeues_from_the_checkpoint(self):
        job_id = self.client.submit(LONG_SPEC)
        first = self.wait_for(job_id, {"running"}, 60)["slurm_job_id"]
        done = self.wait_for(job_id, {"succeeded", "failed", "cancelled"}, 300)
        self.assertEqual(done["status"], "succeeded", done)
        self.assertNotEqual(done["slurm_job_id"], first, "the job ran in one Slurm job: it was never warned")
        self.assertEqual(self.client.curve_csv(job_id), self.local_curve(LONG_SPEC, "local_long"),
                         "the requeued run's curve differs from an uninterrupted local run")

    def test_4_daemon_restart_neither_loses_nor_repeats_jobs(self):
        # Time limits of 6 minutes here: no time-limit warning may requeue these jobs. The first takes 2 s and
        # ends on the cluster while the daemon is down; the second (10 s) runs on across the restart.
        self.stop_daemon()
        self.start_daemon(time_limit=6)
        rates = (3e-6, 6e-7)
        ids = [self.client.submit(short_spec(rate)) for rate in rates]
        running = [self.wait_for(j, {"running"}, 60) for j in ids]
        self.stop_daemon()
        time.sleep(6)  # the workers go on computing; what they make waits for the daemon
        self.start_daemon(time_limit=6)
        done = [self.wait_for(j, {"succeeded", "failed", "cancelled"}, 180) for j in ids]
        for job, before in zip(done, running):
            self.assertEqual(job["status"], "succeeded", f"{job}\n{self.daemon_log()}")
            self.assertEqual(job["slurm_job_id"], before["slurm_job_id"], "the restart submitted it again")
        # slurmctld writes a job's completion record after its worker has told the daemon the end: wait for it.
        def runs(names, j):
            return sum(1 for n in names if n == f"granulab-{j}" or n.startswith(f"granulab-{j}-"))
        deadline = time.time() + 30
        names = [c.get("Name", "") for c in self.cluster.completed()]
        while time.time() < deadline and any(runs(names, j) == 0 for j in ids):
            time.sleep(0.5)
            names = [c.get("Name", "") for c in self.cluster.completed()]
        for j in ids:
            self.assertEqual(runs(names, j), 1, names)
        for job, rate in zip(done, rates):
            self.assertEqual(self.client.curve_csv(job["id"]), self.local_curve(short_spec(rate), f"restart_{rate}"))

    def test_5_a_failing_worker_fails_the_job_with_slurms_reason(self):
        # With a token in SLURM_JWT instead of the key, and a worker that exits 3 at once.
        fake = os.path.join(self.dir, "broken_worker")
        with open(fake, "w") as f:
            f.write("#!/bin/sh\necho broken worker >&2\nexit 3\n")
        os.chmod(fake, 0o755)
        token = subprocess.run(["scontrol", "token", "lifespan=900"], capture_output=True, text=True, check=True,
                               env=dict(os.environ, SLURM_CONF=self.cluster.conf)).stdout.strip().split("=", 1)[1]
        self.stop_daemon()
        self.start_daemon(extra=("--slurm-worker", fake), jwt=token)
        try:
            job = self.wait_for(self.client.submit(short_spec(1e-5)), {"succeeded", "failed", "cancelled"}, 60)
        finally:
            self.stop_daemon()
            self.start_daemon()
        self.assertEqual(job["status"], "failed", job)
        self.assertIn("FAILED", job["error"])
        self.assertIn("exit code 3", job["error"])
        self.assertTrue(job["slurm_state"].startswith("FAILED"), job)

    def test_6_workers_reach_a_daemon_over_https(self):
        # A self-signed certificate made here: the daemon serves HTTPS only, its Slurm jobs are told to trust
        # the certificate (GRANULAB_CA_FILE, by default the --tls-cert file) and their curves are the local ones.
        if not shutil.which("openssl"):
            self.skipTest("no openssl command to make a certificate")
        cert, key = os.path.join(self.dir, "cert.pem"), os.path.join(self.dir, "key.pem")
        subprocess.run(["openssl", "req", "-x509", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1",
                        "-nodes", "-keyout", key, "-out", cert, "-days", "2", "-subj", "/CN=127.0.0.1",
                        "-addext", "subjectAltName=IP:127.0.0.1"], check=True, capture_output=True)
        https = Client(f"https://127.0.0.1:{self.port}", ca_file=cert)
        self.stop_daemon()
        self.start_daemon(time_limit=6, extra=("--tls-cert", cert, "--tls-key", key), client=https)
        try:
            job_id = https.submit(short_spec(2e-5))
            deadline = time.time() + 120
            while time.time() < deadline and https.status(job_id)["status"] not in ("succeeded", "failed", "cancelled"):
                time.sleep(0.3)
            job = https.status(job_id)
            self.assertEqual(job["status"], "succeeded", f"{job}\n{self.daemon_log()}")
            self.assertEqual(https.curve_csv(job_id), self.local_curve(short_spec(2e-5), "local_https"))
        finally:
            self.stop_daemon()
            self.start_daemon()


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import skip_aware  # noqa: E402  (tests/skip_aware.py)


if __name__ == "__main__":
    skip_aware.main(verbosity=2)
