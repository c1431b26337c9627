"""What the Python package's tests share: the package pip-installed offline into a fresh virtual environment, and a
granulabd on loopback with its own SQLite file (tests/clients/python_package_test.py, notebooks_test.py)."""

import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")
SKIP = 77  # ctest's SKIP_RETURN_CODE for these tests


def system_python():
    return "/usr/bin/python3" if os.access("/usr/bin/python3", os.X_OK) else sys.executable


def venv_missing(python):
    """Why this Python cannot make a virtual environment with pip, or None."""
    probe = subprocess.run([python, "-c", "import venv, ensurepip"], capture_output=True)
    return None if probe.returncode == 0 else "%s has no venv/ensurepip (Debian: python3-venv)" % python


def install_package(python, tmp):
    """A virtual environment in tmp/env seeing Debian's packages (the optional extras: pandas, gsd...), the package
    installed into it with no index at all (PIP_NO_INDEX=1: a download attempt fails the install). Returns the
    environment's python, or raises RuntimeError with pip's output."""
    env_dir = os.path.join(tmp, "env")
    subprocess.run([python, "-m", "venv", "--system-site-packages", env_dir], check=True)
    # A copy of the package's folder: pip builds in place, and the checkout stays as it is.
    src = os.path.join(tmp, "src")
    shutil.copytree(os.path.join(ROOT, "clients", "python"), src, ignore=shutil.ignore_patterns("__pycache__"))
    env = dict(os.environ, PIP_NO_INDEX="1", PIP_DISABLE_PIP_VERSION_CHECK="1")
    r = subprocess.run([os.path.join(env_dir, "bin", "pip"), "install", src], env=env, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError("pip install ./clients/python with no index failed:\n" + r.stdout[-3000:] + r.stderr[-3000:])
    return os.path.join(env_dir, "bin", "python")


class Daemon:
    """granulabd on a free loopback port with `workers` workers and a database in tmp; stop() stops it (by PID)."""

    def __init__(self, tmp, workers=2):
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            self.port = s.getsockname()[1]
        self.url = "http://127.0.0.1:%d" % self.port
        self.log = open(os.path.join(tmp, "daemon.log"), "w+")
        self.proc = subprocess.Popen([DAEMON, "--port", str(self.port), "--db", os.path.join(tmp, "t.db"),
                                      "--workers", str(workers)], stdout=self.log, stderr=subprocess.STDOUT,
                                     env=dict(os.environ, OMP_WAIT_POLICY="passive"))
        deadline = time.monotonic() + 20
        while True:
            try:
                with urllib.request.urlopen(self.url + "/v1/health", timeout=2):
                    return
            except OSError:
                if self.proc.poll() is not None or time.monotonic() > deadline:
                    self.stop()
                    raise RuntimeError("granulabd did not start:\n" + self.tail())
                time.sleep(0.1)

    def tail(self):
        self.log.flush()
        self.log.seek(0)
        return self.log.read()[-3000:]

    def stop(self):
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self.log.close()


def run_with_package(prefix, body):
    """body(tmp, env_python, daemon) -> exit code, run with the package installed in a fresh environment and a daemon
    up (both in a new temporary folder, removed after); 1 if either cannot be had."""
    tmp = tempfile.mkdtemp(prefix=prefix)
    daemon = None
    try:
        try:
            env_python = install_package(system_python(), tmp)
            daemon = Daemon(tmp, workers=2)
        except RuntimeError as e:
            print("FAIL:", e)
            return 1
        return body(tmp, env_python, daemon)
    finally:
        if daemon is not None:
            daemon.stop()
        shutil.rmtree(tmp, ignore_errors=True)
