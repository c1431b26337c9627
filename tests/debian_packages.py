"""Debian packages a test needs beyond `make test`'s (Slurm, LAMMPS): installed when missing and root,
else the test is skipped, saying which (ctest shows it as not run, tests/skip_aware.py)."""
import os
import subprocess
import unittest


def installed(package):
    r = subprocess.run(["dpkg-query", "-W", "-f=${Status}", package], capture_output=True, text=True)
    return "ok installed" in r.stdout


def install_missing(packages, what):
    """Installs the missing ones of `packages` with apt-get (update first, waiting up to 10 min for the lock);
    raises unittest.SkipTest naming them when not root."""
    missing = [p for p in packages if not installed(p)]
    if not missing:
        return
    if os.geteuid() != 0:
        raise unittest.SkipTest("%s packages missing and not root: %s" % (what, " ".join(missing)))
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    lock = ["-o", "DPkg::Lock::Timeout=600"]
    subprocess.run(["apt-get", *lock, "update"], check=True, env=env, stdout=subprocess.DEVNULL)
    subprocess.run(["apt-get", *lock, "install", "-y", "--no-install-recommends", *missing], check=True, env=env,
                   stdout=subprocess.DEVNULL)
