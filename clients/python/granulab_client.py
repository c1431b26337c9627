#!/usr/bin/env python3
"""Standard-library-only Python client for the granulab lab server (granulabd).

    from granulab_client import Client, key_values
    c = Client()                        # GRANULAB_SERVER or http://127.0.0.1:8080
    job = c.submit({"experiment": "two_cube_sliding"})
    c.wait(job)
    curve = c.curve(job)                # {"columns": [...], "<name>": [...], ...}
    st = c.status(job)                  # "summary" once it succeeded
    for label, value, unit, reason in key_values(st, c.headline(st["experiment"])):
        print(label, reason if value is None else f"{value:.3g} {unit}")   # reason: "none to 1 % strain (...)"

Command line (prints JSON, or CSV for `curve --csv`):

    granulab_client.py [--server URL] submit SPEC.json [--reuse] [--priority N]
    granulab_client.py [--server URL] status ID | wait ID | cancel ID | snapshots ID
    granulab_client.py [--server URL] curve ID [--csv]
    granulab_client.py [--server URL] list [--status S] [--limit N] [--offset N]
    granulab_client.py [--server URL] health | experiments

Requires Python >= 3.9 and nothing outside the standard library.
"""

import argparse
import collections
import json
import os
import socket
import ssl
import sys
import time
import urllib.error
import urllib.parse
import urllib.request

__all__ = ["Client", "GranulabError", "DEFAULT_SERVER", "KeyValue", "key_values"]

DEFAULT_SERVER = "http://127.0.0.1:8080"
TERMINAL = ("succeeded", "failed", "cancelled")


class GranulabError(Exception):
    """An error reported by the server (status is the HTTP status, 0 if the server is unreachable)."""

    def __init__(self, status, code="error", message="", field=""):
        self.status = int(status)
        self.code = code or "error"
        self.message = message or ""
        self.field = field or ""
        super().__init__(str(self))

    def __str__(self):
        text = f"HTTP {self.status} {self.code}: {self.message}" if self.status else \
            f"{self.code}: {self.message}"
        if self.field:
            text += f" (field '{self.field}')"
        return text


# -- key values ------------------------------------------------------------------------------------
KeyValue = collections.namedtuple("KeyValue", "label value unit reason")
KeyValue.__doc__ = """One key value of a job: its label, its number (None when there is none), its unit, and the
reason there is none when the job's summary says it was not found (else None)."""


def _at(obj, dotted):
    """The value at a dotted path of nested dicts ("first_yield.strain"), or None."""
    for key in dotted.split("."):
        if not isinstance(obj, dict):
            return None
        obj = obj.get(key)
    return obj


def key_values(item, headline):
    """A job's key values as its experiment's headline names them: a list of KeyValue(label, value, unit, reason),
    one per headline value, in the headline's order (what the web page, `granulab wait` and sweep.csv show).

    item: a job's status dict (Client.status(), Client.wait(): its "summary" is read) or one of a sweep's "jobs"
    (Client.sweep(): it holds the same summary groups itself). headline: the experiment's "headline" from
    GET /v1/experiments (Client.headline(name)), or the experiment's whole entry there.

    value is the number at the value's key (a dotted summary path) in `unit` ("p0": per the spec's
    loading.confining_pressure; "-": a ratio). A value that may not exist names a summary group in its
    "status"; when that group says {"found": false}, value is None and reason is the group's reason, e.g.
    "none to 0.053 % strain (no drop after its largest, 41.4 p0)": a crystal that never yields has no first
    yield, and the largest stress reached is not one. A job with no such number yet (queued, running, failed,
    cancelled) gives value and reason None.
    """
    if isinstance(headline, dict) and isinstance(headline.get("headline"), dict):
        headline = headline["headline"]
    if not isinstance(item, dict):
        raise TypeError("key_values: item is a job's status dict or a sweep's job item")
    # A job's status dict keeps its results under "summary" (absent until it succeeds); a sweep's item holds them.
    summary = item.get("summary") if ("summary" in item or "spec" in item) else item
    if not isinstance(summary, dict):
        summary = {}
    values = []
    for v in (headline or {}).get("values", []):
        group = _at(summary, v["status"]) if v.get("status") else None
        if isinstance(group, dict) and group.get("found") is False:
            reason = group.get("reason")
            values.append(KeyValue(v["label"], None, v["unit"], reason if isinstance(reason, str) else "none"))
            continue
        number = _at(summary, v["key"])
        found = isinstance(number, (int, float)) and not isinstance(number, bool)
        values.append(KeyValue(v["label"], number if found else None, v["unit"], None))
    return values


class Client:
    def __init__(self, server=None, timeout=30.0, token=None, retries=3, ca_file=None):
        # token: an access token of a server started with --token-file (default: GRANULAB_TOKEN).
        # ca_file: for an https server, the PEM certificate(s) to trust beside the system's: a lab's own,
        # self-signed one (default: GRANULAB_CA_FILE). The server's name is checked against it.
        # retries: how many times a request the server never answered is tried again (0.5, 1, 2 s apart):
        # a restarting daemon or a dropped connection is not an error for a script polling a long sweep.
        self.token = token or os.environ.get("GRANULAB_TOKEN")
        self.retries = retries
        server = server or os.environ.get("GRANULAB_SERVER") or DEFAULT_SERVER
        if "://" not in server:
            server = "http://" + server
        self.server = server.rstrip("/")
        self.timeout = timeout
        ca_file = ca_file or os.environ.get("GRANULAB_CA_FILE")
        self._tls = ssl.create_default_context(cafile=ca_file) if self.server.startswith("https://") else None

    # -- transport -------------------------------------------------------------------------------
    def _request(self, method, path, query=None, body=None, raw=False, binary=False):
        for attempt in range(self.retries + 1):
            try:
                return self._request_once(method, path, query, body, raw, binary)
            except GranulabError as e:
                # Only what never reached an answer: a refused or reset connection, or 503 (too many
                # connections). A POST is retried only when refused (it cannot have been received).
                refused = e.code == "unreachable" and "refused" in (e.message or "").lower()
                transient = (e.code == "unreachable" and (method != "POST" or refused)) or e.status == 503
                if not transient or attempt == self.retries:
                    raise
                time.sleep(0.5 * 2 ** attempt)

    def _request_once(self, method, path, query=None, body=None, raw=False, binary=False):
        url = self.server + path
        if query:
            query = {k: v for k, v in query.items() if v is not None}
            if query:
                url += "?" + urllib.parse.urlencode(query)
        data = None
        headers = {"Accept": "application/json"}
        if self.token:
            headers["Authorization"] = "Bearer " + self.token
        if method == "POST":
            # Always a body (possibly empty), so Content-Length is set for any server or proxy.
            data = body if isinstance(body, bytes) else (body or "").encode("utf-8")
            headers["Content-Type"] = "application/json"
        req = urllib.request.Request(url, data=data, method=method, headers=headers)
        try:
            with urllib.request.urlopen(req, timeout=self.timeout, context=self._tls) as resp:
                payload = resp.read()
                if binary:
                    return payload
                payload = payload.decode("utf-8")
                status = resp.status
        except urllib.error.HTTPError as e:
            raise self._error_from(e.code, e.read().decode("utf-8", "replace")) from None
        except urllib.error.URLError as e:
            # A timeout is an answer that did not come in time, not an unreachable server: never retried (the
            # server may still be working on it; asking again would repeat the work). A certificate that does
            # not verify is not retried either.
            if isinstance(e.reason, ssl.SSLError):
                raise GranulabError(0, "tls", f"cannot speak TLS with {self.server}: {e.reason} (for a "
                                    "certificate of the lab's own, give ca_file or GRANULAB_CA_FILE)") from None
            code = "timeout" if isinstance(e.reason, (TimeoutError, socket.timeout)) else "unreachable"
            raise GranulabError(0, code, f"cannot reach {self.server}: {e.reason}") from None
        except ssl.SSLError as e:
            raise GranulabError(0, "tls", f"cannot speak TLS with {self.server}: {e}") from None
        except (TimeoutError, socket.timeout) as e:
            raise GranulabError(0, "timeout", f"{self.server} did not answer within {self.timeout} s: {e}") from None
        except (ConnectionError, OSError) as e:  # e.g. reset mid-response
            raise GranulabError(0, "unreachable", f"cannot reach {self.server}: {e}") from None
        if raw:
            return payload
        try:
            result = json.loads(payload) if payload else {}
        except ValueError:
            raise GranulabError(status, "bad_response", f"server sent non-JSON: {payload[:200]!r}") from None
        return result

    @staticmethod
    def _error_from(status, text):
        try:
            err = json.loads(text).get("error") or {}
            if not isinstance(err, dict):
                err = {"message": str(err)}
        except (ValueError, AttributeError):
            err = {"message": text.strip()[:500]}
        return GranulabError(status, err.get("code"), err.get("message"), err.get("field"))

    @staticmethod
    def _spec_body(spec):
        if isinstance(spec, dict):
            return json.dumps(spec)
        if isinstance(spec, (str, os.PathLike)) and os.path.exists(spec):
            with open(spec, encoding="utf-8") as f:
                return f.read()
        if isinstance(spec, str) and spec.lstrip().startswith("{"):
            return spec
        raise FileNotFoundError(f"spec file not found: {spec}")

    # -- API ---------------------------------------------------------------------------------------
    def submit(self, spec, reuse=False, priority=None):
        """Submit a spec (a dict, a JSON string, or a path to a JSON file). Returns the job id."""
        body = self._spec_body(spec)
        query = {}
        if reuse:
            query["reuse"] = "true"
        if priority is not None:
            query["priority"] = int(priority)
        return int(self._request("POST", "/v1/jobs", query, body)["id"])

    def dry_run(self, spec):
        """What a spec would cost on this server, without queueing it: spheres, grains, steps, memory_bytes,
        expected_seconds (at the server's recent speed) and over_budget when it would be refused."""
        return self._request("POST", "/v1/jobs", {"dry_run": "true"}, self._spec_body(spec))

    def status(self, job_id):
        return self._request("GET", f"/v1/jobs/{int(job_id)}")

    def wait(self, job_id, timeout=None, poll=0.5, on_progress=None):
        """Poll until the job finishes. Returns the final status dict if it succeeded; raises
        GranulabError on failed/cancelled and TimeoutError if `timeout` seconds pass first."""
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            st = self.status(job_id)
            if on_progress is not None:
                on_progress(st)
            state = st.get("status")
            if state == "succeeded":
                return st
            if state in ("failed", "cancelled"):
                message = st.get("error") or f"job {job_id} {state}"
                if isinstance(message, dict):
                    message = message.get("message", json.dumps(message))
                raise GranulabError(0, state, str(message))
            if deadline is not None and time.monotonic() >= deadline:
                raise TimeoutError(f"job {job_id} still {state} after {timeout} s")
            time.sleep(poll if deadline is None else max(0.0, min(poll, deadline - time.monotonic())))

    def wait_all(self, job_ids, timeout=None, poll=1.0, on_progress=None):
        """Poll until every job has finished; returns {id: final status dict} (failed and cancelled jobs
        included: check each "status"). on_progress(list of status dicts) is called at every poll; raises
        TimeoutError if `timeout` seconds pass first."""
        deadline = None if timeout is None else time.monotonic() + timeout
        done = {}
        while True:
            current = [done.get(int(i)) or self.status(i) for i in job_ids]
            for st in current:
                if st.get("status") in ("succeeded", "failed", "cancelled"):
                    done[int(st["id"])] = st
            if on_progress is not None:
                on_progress(current)
            if len(done) == len(set(int(i) for i in job_ids)):
                return done
            if deadline is not None and time.monotonic() >= deadline:
                raise TimeoutError(f"{len(set(int(i) for i in job_ids)) - len(done)} jobs still unfinished after {timeout} s")
            time.sleep(poll if deadline is None else max(0.0, min(poll, deadline - time.monotonic())))

    def curve(self, job_id):
        """The curve as columns: {"columns": [names], name: [values], ...}; while the job runs, the rows
        computed so far."""
        return self._request("GET", f"/v1/jobs/{int(job_id)}/curve")

    def to_pandas(self, job_id):
        """The curve as a pandas DataFrame (pandas is never a dependency: ImportError without it)."""
        try:
            import pandas
        except ImportError:
            raise ImportError("to_pandas needs pandas (Debian: python3-pandas); curve() gives the same columns") from None
        c = self.curve(job_id)
        return pandas.DataFrame({name: c[name] for name in c["columns"]})

    def snapshot_file(self, job_id, k, fmt="dump", step=None):
        """Snapshot k as text in `fmt`: "dump" (LAMMPS, for OVITO; "dump_spheres": every sphere), "vtk" or
        "vtk_interfaces" (ParaView), "json",
        the contact network "contacts_vtk" or "contacts_dump" (a LAMMPS local dump), the grains' polyhedra "mesh_vtk", or
        the front face's DIC-like map, "dic_csv" or "dic_vtk", on a grid of `step` m (default: half a grain spacing)."""
        query = {"format": fmt}
        if step is not None:
            query["step"] = repr(float(step))
        return self._request("GET", f"/v1/jobs/{int(job_id)}/snapshots/{int(k)}", query, raw=True)

    def archive(self, job_id, path):
        """Saves everything of a job (spec, summary, curve, every snapshot in its nine files, all formats but the per-sphere dump_spheres) as a tar at `path`."""
        data = self._request("GET", f"/v1/jobs/{int(job_id)}/archive", raw=True, binary=True)
        with open(path, "wb") as f:
            f.write(data)
        return path

    def curve_csv(self, job_id):
        return self._request("GET", f"/v1/jobs/{int(job_id)}/curve", {"format": "csv"}, raw=True)

    def snapshots(self, job_id):
        return self._request("GET", f"/v1/jobs/{int(job_id)}/snapshots").get("snapshots", [])

    def snapshot(self, job_id, k):
        return self._request("GET", f"/v1/jobs/{int(job_id)}/snapshots/{int(k)}")

    def cancel(self, job_id):
        return self._request("POST", f"/v1/jobs/{int(job_id)}/cancel")

    def delete(self, job_id):
        """Deletes a finished job with its curve and snapshots (owner or admin)."""
        return self._request("DELETE", f"/v1/jobs/{int(job_id)}")

    def set_priority(self, job_id, priority):
        """A queued job's new priority, -100..100, higher first (owner or admin)."""
        return self._request("POST", f"/v1/jobs/{int(job_id)}/priority", {"value": int(priority)})

    def list(self, status=None, limit=50, offset=0, owner=None):
        return self._request("GET", "/v1/jobs", {"status": status, "limit": limit, "offset": offset,
                                                 "owner": owner}).get("jobs", [])

    def submit_sweep(self, spec, vary, mode="product", label="", priority=None):
        """A sweep of `spec` over `vary` ({"dotted.key": [values]}); returns (sweep id, [job ids]).

        Each value is the field's value as the spec has it, so a field that is itself a list takes a list per
        point: {"loading.axis": [[1, 1, 0], [1, 1, 1]]} is two jobs, one along each axis (likewise
        "output.snapshot_strains": [[0, 0.01], [0, 0.02]]). mode "zip" pairs the lists (they must be as long as
        each other) instead of running every combination."""
        body = json.dumps({"spec": spec, "vary": vary, "mode": mode, "label": label})
        r = self._request("POST", "/v1/sweeps", {"priority": priority}, body=body)
        return r["id"], r["jobs"]

    def sweep(self, sweep_id):
        """The sweep with its jobs: values, status, progress, first yield and peak."""
        return self._request("GET", f"/v1/sweeps/{int(sweep_id)}")

    def sweeps(self, limit=50, offset=0, owner=None):
        return self._request("GET", "/v1/sweeps", {"limit": limit, "offset": offset, "owner": owner}).get("sweeps", [])

    def cancel_sweep(self, sweep_id):
        return self._request("POST", f"/v1/sweeps/{int(sweep_id)}/cancel")

    def health(self):
        return self._request("GET", "/v1/health")

    def experiments(self):
        """Every experiment the server runs: its spec fields (default, range, unit), curve columns and headline."""
        return self._request("GET", "/v1/experiments").get("experiments", [])

    def headline(self, experiment):
        """What `experiment` (its name) shows first, as GET /v1/experiments has it: its key values' labels, units
        and summary paths among them (for key_values()). KeyError for a name the server does not run."""
        for e in self.experiments():
            if e.get("name") == experiment:
                return e["headline"]
        raise KeyError(f"the server runs no experiment named {experiment!r}")


# -- command line ----------------------------------------------------------------------------------
def _print_json(obj):
    json.dump(obj, sys.stdout, indent=2, sort_keys=True)
    sys.stdout.write("\n")


def main(argv=None):
    p = argparse.ArgumentParser(prog="granulab_client.py", description="granulab lab server client")
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
            job = client.submit(a.spec, reuse=a.reuse, priority=a.priority)
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
                             f"(granulab_client.py cancel {a.id} stops it)\n")
        else:
            sys.stderr.write("\ninterrupted\n")
        return 130
    except BrokenPipeError:  # e.g. `... list | head`
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    except (GranulabError, TimeoutError, OSError) as e:
        sys.stderr.write(f"granulab_client: {e}\n")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
