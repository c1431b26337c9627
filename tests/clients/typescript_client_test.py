#!/usr/bin/env python3
"""A TypeScript client generated from docs/openapi.json compiles (issue 53, part 3): openapi-typescript and
openapi-fetch from the npm registry (in this test only, into a temporary folder), the document's types generated
with no hand edits, and tests/clients/typescript/client.ts (a short script using jobs, dry runs, curves, sweeps and
listings as a researcher would) type-checked with `tsc --strict`: 0 errors, and an operation type per operationId.

openapi-typescript runs with `--default-non-nullable false`: by default it makes every property with a `default`
required, and the spec's schema (a component the request bodies and the job replies share) gives most fields a
default that the server fills in. Exits 77 (a skip, said to ctest) without npm or without the registry.
"""

import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
PACKAGES = ["openapi-typescript@7", "openapi-fetch@0", "typescript@5"]
OPERATIONS = ["submitJob", "getJob", "getJobCurve", "submitSweep", "getSweep", "listJobs", "listSweeps", "cancelJob"]


def run(cmd, cwd, timeout):
    return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout)


def main():
    npm = shutil.which("npm")
    if not npm:
        print("SKIPPED: no npm")
        return 77
    tmp = tempfile.mkdtemp(prefix="granulab_ts_")
    try:
        try:
            probe = run([npm, "view", "openapi-typescript@7", "version"], tmp, 90)
        except subprocess.TimeoutExpired:
            probe = None
        if probe is None or probe.returncode != 0:
            print("SKIPPED: the npm registry is not reachable from here")
            return 77
        for name in ("client.ts", "tsconfig.json"):
            shutil.copy(os.path.join(HERE, "typescript", name), tmp)
        r = run([npm, "install", "--no-audit", "--no-fund", "--loglevel=error", "--no-save"] + PACKAGES, tmp, 600)
        if r.returncode != 0:
            print(r.stdout[-2000:], r.stderr[-2000:])
            print("SKIPPED: npm could not install", " ".join(PACKAGES))
            return 77
        bin_dir = os.path.join(tmp, "node_modules", ".bin")
        r = run([os.path.join(bin_dir, "openapi-typescript"), os.path.join(ROOT, "docs", "openapi.json"),
                 "--default-non-nullable", "false", "-o", os.path.join(tmp, "api.d.ts")], tmp, 120)
        if r.returncode != 0:
            print(r.stdout[-3000:], r.stderr[-3000:])
            print("FAIL: openapi-typescript could not generate the client")
            return 1
        with open(os.path.join(tmp, "api.d.ts")) as f:
            types = f.read()
        missing = [op for op in OPERATIONS if not re.search(r"\b%s\b" % op, types)]
        if missing:
            print("FAIL: the generated client has no operation", ", ".join(missing))
            return 1
        r = run([os.path.join(bin_dir, "tsc"), "-p", "."], tmp, 300)
        errors = [line for line in r.stdout.splitlines() if "error TS" in line]
        print("tsc --strict: %d errors" % len(errors))
        if r.returncode != 0 or errors:
            print(r.stdout[-6000:], r.stderr[-2000:])
            print("FAIL: the script does not type-check against the generated client")
            return 1
        return 0
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
