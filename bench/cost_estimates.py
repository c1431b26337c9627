#!/usr/bin/python3
"""Dry-run estimates against measured runs, for the examples (bench/README.md, "Cost estimates").

    /usr/bin/python3 bench/cost_estimates.py [--measured DIR] [--run] [--threads T] [NAME ...]

A daemon on loopback with a fresh SQLite file gives each example's dry run: steps, phases and expected
seconds. The measurement of an example is DIR/NAME/summary.json when --measured DIR has it (what
`granulab run examples/NAME.json --out DIR/NAME --threads T` wrote), else, with --run, the example run on
that daemon (its summary). Every estimate is taken before any job has run there, so it rests on the
benchmark table alone (the harder case: a server with finished jobs of similar size scales the table by
them). Prints a markdown table: steps and seconds, estimated against measured.

Standard library only; build/granulabd (or $GRANULABD).
"""
import argparse
import json
import os
import socket
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "clients", "python"))
from granulab_client import Client  # noqa: E402

DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")


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


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("names", nargs="*", help="examples (default: every examples/*.json)")
    parser.add_argument("--measured", help="folder of `granulab run` outputs, one NAME/summary.json each")
    parser.add_argument("--run", action="store_true", help="run what --measured lacks on the daemon")
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    names = args.names or sorted(f[:-5] for f in os.listdir(os.path.join(ROOT, "examples")) if f.endswith(".json"))

    folder = tempfile.mkdtemp(prefix="granulab-cost-")
    port = free_port()
    daemon = subprocess.Popen([DAEMON, "--port", str(port), "--db", os.path.join(folder, "g.db"), "--workers", "1",
                               "--threads", str(args.threads)],
                              stdout=open(os.path.join(folder, "log"), "w"), stderr=subprocess.STDOUT)
    try:
        client = Client("http://127.0.0.1:%d" % port)
        for _ in range(100):
            try:
                client.health()
                break
            except Exception:
                time.sleep(0.1)
        estimates = {}
        for name in names:
            with open(os.path.join(ROOT, "examples", name + ".json")) as f:
                estimates[name] = client.dry_run(json.load(f))
        print("| example | spheres | steps: estimated / measured | ratio | time: estimated / measured | ratio |")
        print("| --- | --- | --- | --- | --- | --- |")
        for name in names:
            e = estimates[name]
            summary = None
            path = os.path.join(args.measured or "", name, "summary.json")
            if args.measured and os.path.exists(path):
                with open(path) as f:
                    summary = json.load(f)
            elif args.run:
                with open(os.path.join(ROOT, "examples", name + ".json")) as f:
                    job = client.submit(json.load(f))
                client.wait(job)
                summary = client.status(job).get("summary")
            if not summary or "wall_seconds" not in summary:
                print("| %s | %.4g | %.4g / - | - | %s / - | - |" % (name, e["spheres"], e["steps"],
                                                                    duration(e["expected_seconds"])))
                continue
            steps, seconds = summary["steps"], summary["wall_seconds"]
            print("| %s | %.4g | %.4g / %d | %.2f | %s / %s | %.2f |" % (
                name, e["spheres"], e["steps"], steps, e["steps"] / steps, duration(e["expected_seconds"]),
                duration(seconds), e["expected_seconds"] / seconds))
            sys.stdout.flush()
    finally:
        daemon.terminate()
        daemon.wait(timeout=30)


if __name__ == "__main__":
    main()
