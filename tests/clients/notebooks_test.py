#!/usr/bin/env python3
"""The notebooks of examples/notebooks/ executed as a researcher runs them (issue 53, part 4): the package
pip-installed offline into a fresh virtual environment, a Jupyter kernel of that environment, a real granulabd on
loopback, and every cell run by nbclient (Debian's python3-nbclient and python3-ipykernel) with the notebooks' QUICK
sizes (GRANULAB_NOTEBOOK_QUICK=1: tiny crystals). A cell that raises fails the test; so does a notebook stored with
outputs (they are kept without). Exits 77 (a skip, said to ctest) without venv, nbclient or ipykernel.
"""

import glob
import json
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import package_env  # noqa: E402

NOTEBOOKS = sorted(glob.glob(os.path.join(package_env.ROOT, "examples", "notebooks", "*.ipynb")))

RUN = r'''
import sys, nbformat, nbclient
nb = nbformat.read(sys.argv[1], as_version=4)
client = nbclient.NotebookClient(nb, timeout=300, kernel_name="granulab-test", resources={"metadata": {"path": "."}})
client.execute()
shown = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
svg = sum(1 for o in shown if "image/svg+xml" in o.get("data", {}))
print("executed", len(nb.cells), "cells,", svg, "pictures shown inline")
'''


def main():
    python = package_env.system_python()
    missing = package_env.venv_missing(python)
    probe = subprocess.run([python, "-c", "import nbclient, nbformat, ipykernel"], capture_output=True)
    if missing or probe.returncode != 0:
        print("SKIPPED:", missing or "no nbclient/ipykernel (Debian: python3-nbclient, python3-ipykernel)")
        return package_env.SKIP
    if len(NOTEBOOKS) < 2:
        print("FAIL: examples/notebooks/ holds", NOTEBOOKS)
        return 1
    for path in NOTEBOOKS:  # stored without outputs, so that a diff shows what changed in the code
        with open(path) as f:
            nb = json.load(f)
        stored = [c for c in nb["cells"] if c["cell_type"] == "code" and (c.get("outputs") or c.get("execution_count"))]
        if stored:
            print("FAIL: %s is stored with outputs (clear them)" % path)
            return 1
    return package_env.run_with_package("granulab_nb_", execute)


def execute(tmp, env_python, daemon):
    # A kernel of the environment (its python imports the installed package), found through its own prefix.
    subprocess.run([env_python, "-m", "ipykernel", "install", "--sys-prefix", "--name", "granulab-test"], check=True,
                   capture_output=True)
    env = dict(os.environ, GRANULAB_SERVER=daemon.url, GRANULAB_NOTEBOOK_QUICK="1")
    env.pop("PYTHONPATH", None)
    failed = 0
    for path in NOTEBOOKS:
        work = os.path.join(tmp, os.path.basename(path) + ".run")
        os.mkdir(work)
        r = subprocess.run([env_python, "-c", RUN, path], cwd=work, env=env, capture_output=True, text=True,
                           timeout=900)
        print(os.path.basename(path) + ":", r.stdout.strip())
        if r.returncode != 0:
            print(re.sub(r"\x1b\[[0-9;]*m", "", r.stderr)[-5000:])  # without the traceback's colours
            print("FAIL:", path)
            failed += 1
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
