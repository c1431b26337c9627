#!/usr/bin/python3
"""Dry-run estimates against measured runs, for the examples (bench/README.md, "Cost estimates").

    /usr/bin/python3 bench/cost_estimates.py --measured DIR [--run] [--threads T] [NAME ...]

An example's measurement is DIR/NAME/summary.json (what `granulab run examples/NAME.json --threads T`
wrote) and its estimate DIR/NAME/estimate.json, the dry run of a fresh daemon on the same machine taken just
before the run. With --run, what DIR lacks is made, one example at a time: a fresh daemon (a new SQLite file,
so its estimate rests on the benchmark table and its speed probe alone, the harder case: a server with
finished jobs of similar size scales the table by them) answers the dry run and stops, then the example runs
in-process with nothing else on the cores. Without an estimate.json, a fresh daemon's dry run now is used.
Prints a markdown table: steps and seconds, estimated against measured.

Standard library only; build/granulabd and build/granulab (or $GRANULABD, $GRANULAB).
"""
import argparse
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "clients", "python"))
from granulab_client import Client  # noqa: E402

DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")
CLI = os.environ.get("GRANULAB") or os.path.join(ROOT, "build", "granulab")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def duration(s):
    if s < 120:
        return "%.0f s" % s
    if s < 7200:
        return "%.1f min" % (s / 60)
    return "%.2f h" % (s / 3600)


def example(name):
    with open(os.path.join(ROOT, "examples", name + ".json")) as f:
        return json.load(f)


def fresh_dry_runs(names, threads):
    """{name: dry run} from one fresh daemon (its speed probe taken at its start, before any job)."""
    folder = tempfile.mkdtemp(prefix="granulab-cost-")
    port = free_port()
    daemon = subprocess.Popen([DAEMON, "--port", str(port), "--db", os.path.join(folder, "g.db"), "--workers", "1",
                               "--threads", str(threads)],
                              stdout=open(os.path.join(folder, "log"), "w"), stderr=subprocess.STDOUT)
    try:
        client = Client("http://127.0.0.1:%d" % port)
        for _ in range(100):
            try:
                client.health()
                break
            except Exception:
                time.sleep(0.1)
        return {name: client.dry_run(example(name)) for name in names}
    finally:
        daemon.terminate()
        daemon.wait(timeout=30)
        shutil.rmtree(folder, ignore_errors=True)


def measure(name, folder, threads):
    """The dry run, then the whole run, into folder/{estimate,summary}.json."""
    os.makedirs(folder, exist_ok=True)
    estimate = fresh_dry_runs([name], threads)[name]
    with open(os.path.join(folder, "estimate.json"), "w") as f:
        json.dump(estimate, f, indent=1)
    out = os.path.join(folder, "run")
    with open(os.path.join(folder, "run.log"), "w") as log:
        subprocess.run([CLI, "run", os.path.join(ROOT, "examples", name + ".json"), "--out", out, "--threads",
                        str(threads), "--quiet"], stdout=log, stderr=subprocess.STDOUT, check=True)
    shutil.copy(os.path.join(out, "summary.json"), os.path.join(folder, "summary.json"))
    shutil.rmtree(out, ignore_errors=True)  # snapshots of the full crystal are hundreds of MB


def load(path):
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("names", nargs="*", help="examples (default: every examples/*.json)")
    parser.add_argument("--measured", required=True, help="folder of NAME/{estimate,summary}.json")
    parser.add_argument("--run", action="store_true", help="measure what --measured lacks")
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    names = args.names or sorted(f[:-5] for f in os.listdir(os.path.join(ROOT, "examples")) if f.endswith(".json"))
    if args.run:
        for name in names:
            if not os.path.exists(os.path.join(args.measured, name, "summary.json")):
                print("measuring %s" % name, file=sys.stderr)
                measure(name, os.path.join(args.measured, name), args.threads)

    estimates = {name: load(os.path.join(args.measured, name, "estimate.json")) for name in names}
    missing = [name for name in names if estimates[name] is None]
    if missing:
        estimates.update(fresh_dry_runs(missing, args.threads))
    print("| example | spheres | steps: estimated / measured | ratio | time: estimated / measured | ratio |")
    print("| --- | --- | --- | --- | --- | --- |")
    for name in names:
        e = estimates[name]
        summary = load(os.path.join(args.measured, name, "summary.json"))
        if not summary or "wall_seconds" not in summary:
            print("| %s | %.4g | %.4g / - | - | %s / - | - |" % (name, e["spheres"], e["steps"],
                                                                duration(e["expected_seconds"])))
            continue
        steps, seconds = summary["steps"], summary["wall_seconds"]
        print("| %s | %.4g | %.4g / %d | %.2f | %s / %s | %.2f |" % (
            name, e["spheres"], e["steps"], steps, e["steps"] / steps, duration(e["expected_seconds"]),
            duration(seconds), e["expected_seconds"] / seconds))


if __name__ == "__main__":
    main()
