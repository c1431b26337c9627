#!/usr/bin/python3
"""The README tutorial's numbers, regenerated (and, with --check, compared with what README.md prints):

    /usr/bin/python3 examples/tutorial_numbers.py [--check README.md] [--pictures docs/pictures] [--threads 2]

Does what the tutorial does, on a daemon of its own (loopback, a fresh SQLite file, one worker): the dry
run of examples/fig7c_p30.json, then the sweep of examples/crystal_quick.json over 10, 30 and 60 kPa with
`granulab sweep`. Prints the output blocks and sentences the README quotes (about a minute on 2 cores); with --pictures, the README's pictures of those
runs (and of the two-cube example).
With --check it fails (exit 1, naming each) when a number the README prints is not what the code gives now:
physics within 0.02 p0 or 3 %, steps within 3 %, the dry run's sizes, steps and memory within 1 % (they come
from the spec alone). Durations and speeds are the machine's and are not checked.

Standard library only; build/granulab and build/granulabd (or $GRANULAB, $GRANULABD).
"""
import argparse
import json
import os
import re
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GRANULAB = os.environ.get("GRANULAB") or os.path.join(ROOT, "build", "granulab")
DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")
NUMBER = r"[-+]?[0-9][0-9,]*(?:\.[0-9]+)?(?:e[-+]?[0-9]+)?"


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def value(text):
    return float(text.replace(",", ""))


def fetch(port, path, out):
    with urllib.request.urlopen("http://127.0.0.1:%d%s" % (port, path), timeout=60) as r, open(out, "wb") as f:
        f.write(r.read())


def draw_pictures(port, env, sweep_id, job_30kpa, folder):
    """The README's pictures: the sweep's curves, the 30 kPa job's curve and sections at 1 %, two cubes."""
    os.makedirs(folder, exist_ok=True)
    fetch(port, "/v1/sweeps/%d/curves.svg" % sweep_id, os.path.join(folder, "sweep_pressures.svg"))
    fetch(port, "/v1/jobs/%d/curve.svg" % job_30kpa, os.path.join(folder, "crystal_curve.svg"))
    for field in ("equivalent_strain", "penetration_ratio"):
        fetch(port, "/v1/jobs/%d/snapshots/2.svg?field=%s" % (job_30kpa, field),
              os.path.join(folder, "crystal_%s.svg" % field))
    job = subprocess.run([GRANULAB, "submit", os.path.join(ROOT, "examples", "two_cube_f03.json")], env=env,
                         check=True, capture_output=True, text=True).stdout.strip()
    subprocess.run([GRANULAB, "wait", job], env=env, check=True, capture_output=True)
    fetch(port, "/v1/jobs/%s/curve.svg" % job, os.path.join(folder, "two_cube_f03.svg"))


def regenerate(threads, pictures=None):
    """Runs the tutorial's steps 3 and 4; returns {'dry_run': line, 'jobs': [lines], 'facts': [sentences]}.
    With `pictures`, also draws the README's pictures there."""
    folder = tempfile.mkdtemp(prefix="granulab-tutorial-")
    port = free_port()
    env = dict(os.environ, GRANULAB_SERVER="http://127.0.0.1:%d" % port)
    env.pop("GRANULAB_TOKEN", None)
    daemon = subprocess.Popen([DAEMON, "--port", str(port), "--db", os.path.join(folder, "g.db"), "--workers", "1",
                               "--threads", str(threads)],
                              stdout=open(os.path.join(folder, "daemon.log"), "w"), stderr=subprocess.STDOUT)
    try:
        for _ in range(100):
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                time.sleep(0.1)
        dry = subprocess.run([GRANULAB, "submit", os.path.join(ROOT, "examples", "fig7c_p30.json"), "--dry-run"],
                             env=env, check=True, capture_output=True, text=True).stdout.strip()
        start = time.monotonic()
        sweep = subprocess.run([GRANULAB, "sweep", os.path.join(ROOT, "examples", "crystal_quick.json"), "--vary",
                                "loading.confining_pressure=10e3,30e3,60e3", "--out", os.path.join(folder, "p0")],
                               env=env, check=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True).stdout
        seconds = time.monotonic() - start
        with open(os.path.join(folder, "sweep.out"), "w") as f:
            f.write(sweep)
        finals = {}
        for line in sweep.splitlines():
            m = re.match(r"job (\d+)\s+succeeded", line)
            if m:
                finals[int(m.group(1))] = line.rstrip()
        with open(os.path.join(folder, "p0", "sweep.csv")) as f:
            ids = sorted(int(row.split(",")[0]) for row in f.read().splitlines()[1:] if row)
        missing = [j for j in ids if j not in finals]
        if missing:
            raise RuntimeError("the sweep printed no final line for job(s) %s (%s)" % (missing, folder))
        summaries = []
        for job in ids:
            with open(os.path.join(folder, "p0", str(job), "summary.json")) as f:
                summaries.append(json.load(f))
        p0s = [s["spec"]["loading"]["confining_pressure"] for s in summaries]
        order = sorted(range(len(ids)), key=lambda k: p0s[k])
        fy = [summaries[k]["first_yield"]["deviator_over_p0"] for k in order]
        peak = [summaries[k]["peak"]["deviator_over_p0"] for k in order]
        steps = [summaries[k]["steps"] for k in order]
        walls = [summaries[k]["wall_seconds"] for k in order]
        if pictures:
            sweep_id = int(re.search(r"^sweep (\d+):", sweep, re.M).group(1))
            draw_pictures(port, env, sweep_id, ids[order[1]], pictures)
        facts = [
            "first yields of %.2f, %.2f and %.2f p0" % tuple(fy),
            "peaks to 1 %% strain of %.2f, %.2f and %.2f p0" % tuple(peak),
            "%s, %s and %s steps" % tuple("{:,}".format(s) for s in steps),
        ]
        return {"dry_run": dry, "jobs": [finals[j] for j in ids], "facts": facts,
                "times": "jobs of %.0f, %.0f and %.0f s; the sweep %.0f s" % (walls[0], walls[1], walls[2], seconds)}
    finally:
        daemon.terminate()
        daemon.wait(timeout=30)


def numbers(text):
    return [value(x) for x in re.findall(NUMBER, text)]


def close(a, b, kind):
    if kind == "dry_run":
        return abs(a - b) <= 0.01 * abs(b) + 1e-12
    if kind == "steps":
        return abs(a - b) <= 0.03 * abs(b)
    return abs(a - b) <= max(0.02, 0.03 * abs(b))


def template(sentence):
    """A regex of the sentence with every number a group."""
    parts = re.split("(" + NUMBER + ")", sentence)
    return "".join("(" + NUMBER + ")" if k % 2 else re.escape(p) for k, p in enumerate(parts))


def check(readme_path, got):
    with open(readme_path) as f:
        readme = f.read()
    problems = []

    def compare(label, printed, regenerated, kind):
        a, b = numbers(printed), numbers(regenerated)
        if len(a) != len(b):
            problems.append("%s: the README has '%s', the code gives '%s'" % (label, printed, regenerated))
            return
        for x, y in zip(a, b):
            if not close(x, y, kind):
                problems.append("%s: the README prints %g, the code gives %g ('%s')" % (label, x, y, regenerated))

    # Only the tutorial's section: the rest of the README quotes other runs.
    start = readme.find("## Ten-minute tutorial")
    end = readme.find("\n## ", start + 1)
    readme = readme[start:end if end > 0 else len(readme)]
    # The dry run: its line, up to the memory (the expected time is this machine's and its history's).
    head = got["dry_run"].split("; about")[0]
    found = re.search(template(head), readme)
    if not found:
        problems.append("the dry run: the README has no line like '%s'" % head)
    else:
        compare("the dry run", found.group(0), head, "dry_run")
    # The sweep's final job lines, in order (their ids follow the server's earlier jobs; the bar aside).
    printed = re.findall(r"^job \d+\s+succeeded.*$", readme, re.M)
    if len(printed) != len(got["jobs"]):
        problems.append("the sweep: the README has %d final job lines, the code prints %d" %
                        (len(printed), len(got["jobs"])))
    for k, (old, line) in enumerate(zip(printed, got["jobs"])):
        tail = lambda s: s.split("100.0 %", 1)[-1]
        compare("the sweep's job line %d" % (k + 1), tail(old), tail(line), "physics")
    for fact in got["facts"]:
        found = re.search(template(fact), readme)
        if not found:
            problems.append("the README does not say '%s'" % fact)
        else:
            compare("'%s'" % fact, found.group(0), fact, "steps" if fact.endswith("steps") else "physics")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--check", metavar="README", help="compare with what this file prints; exit 1 if stale")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--pictures", metavar="DIR", help="also draw the README's pictures there (docs/pictures)")
    args = parser.parse_args()
    got = regenerate(args.threads, args.pictures)
    print("dry run:\n  " + got["dry_run"])
    print("sweep, final lines:")
    for line in got["jobs"]:
        print("  " + line)
    print("sentences:")
    for fact in got["facts"]:
        print("  " + fact)
    print("times here (not checked): " + got["times"])
    if args.check:
        problems = check(args.check, got)
        for p in problems:
            print("STALE: " + p)
        if problems:
            sys.exit(1)
        print("%s matches the code" % args.check)


if __name__ == "__main__":
    main()
