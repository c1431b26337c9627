#!/usr/bin/python3
"""The README tutorial's numbers, regenerated (and, with --check, compared with what README.md prints):

    /usr/bin/python3 examples/tutorial_numbers.py [--check README.md] [--pictures docs/pictures] [--threads 2]

Does what the tutorial does, on a daemon of its own (loopback, a fresh SQLite file, one worker): the dry
run of examples/fig7c_p30.json, then the sweep of examples/crystal_quick.json over 10, 30 and 60 kPa with
`granulab sweep`. Prints the output blocks and sentences the README quotes (about a minute on 2 cores); with --pictures, the README's pictures of those
runs (and of the two-cube example).
Then runs, in-process (`granulab run`), the examples whose numbers the README quotes beside their commands
outside the tutorial: examples/shear_fcc_111.json, examples/shear_cubes.json, examples/stiffness_paper_ne4.json,
the tutorial's crystal with contact.normal hertz/material and examples/tension_dmt_ne4.json (2 min 38 s in all, the
tutorial's part included, with --threads 1 on a busy 2-core AMD EPYC, 2026-12-07).
With --check it fails (exit 1, naming each) when a number the README prints is not what the code gives now:
physics within 0.02 p0 or 3 %, steps within 3 %, the dry run's sizes, steps and memory within 1 % (they come
from the spec alone), the examples' numbers within 1 % (0.765 quoted for a peak of 0.747 is another run's). Durations and speeds are the machine's and are not checked.

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
        # The largest deviator to 1 %, from the curve: a peak only where the curve falls after it (the summary's
        # peak has found: false, and no number, for a crystal still hardening at 1 %).
        largest = []
        for k in order:
            with open(os.path.join(folder, "p0", str(ids[k]), "curve.csv")) as f:
                rows = f.read().splitlines()
            column = rows[0].split(",").index("deviator")
            largest.append(max(float(r.split(",")[column]) for r in rows[1:] if r) / p0s[k])
        peak_found = [summaries[k]["peak"]["found"] for k in order]
        steps = [summaries[k]["steps"] for k in order]
        walls = [summaries[k]["wall_seconds"] for k in order]
        if pictures:
            sweep_id = int(re.search(r"^sweep (\d+):", sweep, re.M).group(1))
            draw_pictures(port, env, sweep_id, ids[order[1]], pictures)
        facts = [
            "first yields of %.2f, %.2f and %.2f p0" % tuple(fy),
            "largest deviators to 1 %% strain, %.2f, %.2f and %.2f p0" % tuple(largest),
            {(False, False, True): "only the last of them is a peak", (False, False, False): "none of them is a peak",
             (True, True, True): "each of them is a peak",
             (False, True, True): "the 10 kPa crystal still hardens at 1 %"}.get(tuple(peak_found), "peaks found: %s" % peak_found),
            "%s, %s and %s steps" % tuple("{:,}".format(s) for s in steps),
        ]
        return {"dry_run": dry, "jobs": [finals[j] for j in ids], "facts": facts, "summary_30kpa": summaries[order[1]],
                "times": "jobs of %.0f, %.0f and %.0f s; the sweep %.0f s" % (walls[0], walls[1], walls[2], seconds)}
    finally:
        daemon.terminate()
        daemon.wait(timeout=30)


def run_example(name, threads, folder):
    """`granulab run examples/<name>.json`; its summary."""
    out = os.path.join(folder, name)
    subprocess.run([GRANULAB, "run", os.path.join(ROOT, "examples", name + ".json"), "--out", out, "--threads",
                    str(threads), "--quiet"], check=True, capture_output=True)
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def example_facts(threads, hooke):
    """The sentences the README prints beside the commands of the shear, stiffness, interface-law and tension
    examples; `hooke`: the summary of the tutorial's crystal at 30 kPa (the sweep's middle job)."""
    folder = tempfile.mkdtemp(prefix="granulab-examples-")
    with open(os.path.join(ROOT, "examples", "crystal_quick.json")) as f:
        spec = json.load(f)
    spec["contact"] = {"normal": "hertz/material"}
    hertz_spec = os.path.join(folder, "hertz.json")
    with open(hertz_spec, "w") as f:
        json.dump(spec, f)
    subprocess.run([GRANULAB, "run", hertz_spec, "--out", os.path.join(folder, "hertz"), "--threads", str(threads),
                    "--quiet"], check=True, capture_output=True)
    with open(os.path.join(folder, "hertz", "summary.json")) as f:
        hertz = json.load(f)
    shear = run_example("shear_fcc_111", threads, folder)
    cubes = run_example("shear_cubes", threads, folder)
    stiffness = run_example("stiffness_paper_ne4", threads, folder)
    tension = run_example("tension_dmt_ne4", threads, folder)
    return [
        "rides an edge: peak τ/σn %.3f at γ = %.2f %%, dilation %.1f° at the peak" %
        (shear["peak"]["shear_over_normal"], 100 * shear["peak"]["shear_strain"], shear["dilation_angle"]),
        "cubes sheared on a cube face peak at f: %.3f at f = 0.35, at γ = %.2f %%" %
        (cubes["peak"]["shear_over_normal"], 100 * cubes["peak"]["shear_strain"]),
        "Young's modulus along the paper's axis is {:,.0f} MPa relaxed and {:,.0f} MPa affine".format(
            stiffness["along_axis"]["relaxed"] / 1e6, stiffness["along_axis"]["affine"] / 1e6),
        "lowers the apparent modulus from %.0f MPa to %.0f MPa and leaves the first yield within %.1f %% (%.2f against %.2f p0)" %
        (hooke["apparent_modulus"]["value"] / 1e6, hertz["apparent_modulus"]["value"] / 1e6,
         100 * abs(hertz["first_yield"]["deviator_over_p0"] / hooke["first_yield"]["deviator_over_p0"] - 1),
         hertz["first_yield"]["deviator_over_p0"], hooke["first_yield"]["deviator_over_p0"]),
        "holds %.0f kPa and fails at a strain of %.1fe-5" %
        (tension["tensile_strength"] / 1e3, tension["failure_strain"] / 1e-5),
    ]


def numbers(text):
    return [value(x) for x in re.findall(NUMBER, text)]


def close(a, b, kind):
    if kind == "dry_run":
        return abs(a - b) <= 0.01 * abs(b) + 1e-12
    if kind == "steps":
        return abs(a - b) <= 0.03 * abs(b)
    if kind == "example":
        return abs(a - b) <= 0.01 * abs(b)
    return abs(a - b) <= max(0.02, 0.03 * abs(b))


def template(sentence):
    """A regex of the sentence with every number a group."""
    parts = re.split("(" + NUMBER + ")", sentence)
    # A space matches any run of white space: the README may break a sentence across lines.
    text = lambda p: r"\s+".join(re.escape(w) for w in re.split(r"\s+", p))
    return "".join("(" + NUMBER + ")" if k % 2 else text(p) for k, p in enumerate(parts))


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

    # The examples beyond the tutorial: their sentences anywhere in the README.
    for fact in got.get("examples", []):
        found = re.search(template(fact), readme)
        if not found:
            problems.append("the README does not say '%s'" % fact)
        else:
            compare("'%s'" % fact, found.group(0), fact, "example")
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
    got["examples"] = example_facts(args.threads, got["summary_30kpa"])
    print("dry run:\n  " + got["dry_run"])
    print("sweep, final lines:")
    for line in got["jobs"]:
        print("  " + line)
    print("sentences:")
    for fact in got["facts"]:
        print("  " + fact)
    print("the examples' sentences:")
    for fact in got["examples"]:
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
