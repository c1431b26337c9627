"""The package's command line: `python -m granulab` (or granulab-client): prints the server's JSON (CSV for
`curve --csv`).

    python -m granulab [--server URL] submit SPEC.json [--reuse] [--priority N]
    python -m granulab [--server URL] status ID | wait ID | cancel ID | snapshots ID
    python -m granulab [--server URL] curve ID [--csv]
    python -m granulab [--server URL] list [--status S] [--limit N] [--offset N]
    python -m granulab [--server URL] health | experiments
"""

import argparse
import json
import os
import sys

from granulab.client import DEFAULT_SERVER, Client, GranulabError

def _print_json(obj):
    json.dump(obj, sys.stdout, indent=2, sort_keys=True)
    sys.stdout.write("\n")


def main(argv=None, prog="python -m granulab"):
    p = argparse.ArgumentParser(prog=prog, description="granulab lab server client")
    p.add_argument("--server", help=f"server URL (default: $GRANULAB_SERVER or {DEFAULT_SERVER})")
    sub = p.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("submit", help="submit SPEC.json, print the new job")
    s.add_argument("spec")
    s.add_argument("--reuse", action="store_true", help="reuse a stored result for an identical spec")
    s.add_argument("--priority", type=int)
    for name in ("status", "wait", "cancel", "delete", "snapshots"):
        sub.add_parser(name).add_argument("id", type=int)
    pr = sub.add_parser("priority", help="change a queued job's priority")
    pr.add_argument("id", type=int)
    pr.add_argument("value", type=int)
    c = sub.add_parser("curve")
    c.add_argument("id", type=int)
    c.add_argument("--csv", action="store_true")
    sub.choices["wait"].add_argument("--timeout", type=float)
    ls = sub.add_parser("list")
    ls.add_argument("--status")
    ls.add_argument("--limit", type=int, default=50)
    ls.add_argument("--offset", type=int, default=0)
    ls.add_argument("--owner")
    sub.add_parser("health")
    sub.add_parser("experiments", help="every experiment: spec fields with defaults, ranges, units; curve columns")
    a = p.parse_args(argv)

    client = Client(a.server)
    try:
        if a.cmd == "submit":
            job = client.submit_id(a.spec, reuse=a.reuse, priority=a.priority)
            _print_json(client.status(job) if a.reuse else {"id": job})
        elif a.cmd == "status":
            _print_json(client.status(a.id))
        elif a.cmd == "wait":
            def report(st):
                sys.stderr.write(f"\rjob {a.id}: {st.get('status')} {100 * float(st.get('progress') or 0):5.1f}%")
                sys.stderr.flush()
            try:
                st = client.wait(a.id, timeout=a.timeout, on_progress=report if sys.stderr.isatty() else None)
            finally:
                if sys.stderr.isatty():
                    sys.stderr.write("\n")
            _print_json(st)
        elif a.cmd == "curve":
            if a.csv:
                sys.stdout.write(client.curve_csv(a.id))
            else:
                _print_json(client.curve(a.id))
        elif a.cmd == "cancel":
            _print_json(client.cancel(a.id))
        elif a.cmd == "delete":
            _print_json(client.delete(a.id))
        elif a.cmd == "priority":
            _print_json(client.set_priority(a.id, a.value))
        elif a.cmd == "snapshots":
            _print_json(client.snapshots(a.id))
        elif a.cmd == "list":
            _print_json(client.list(status=a.status, limit=a.limit, offset=a.offset, owner=a.owner))
        elif a.cmd == "health":
            _print_json(client.health())
        elif a.cmd == "experiments":
            _print_json(client.experiments())
    except KeyboardInterrupt:  # Ctrl-C stops this client, not the job: say so instead of a traceback
        if a.cmd == "wait":
            sys.stderr.write(f"\nstopped waiting; job {a.id} goes on on the server "
                             f"({prog} cancel {a.id} stops it)\n")
        else:
            sys.stderr.write("\ninterrupted\n")
        return 130
    except BrokenPipeError:  # e.g. `... list | head`
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    except (GranulabError, TimeoutError, OSError) as e:
        sys.stderr.write(f"{prog}: {e}\n")
        return 1
    return 0
