"""The transport and the HTTP API of the granulab lab server (granulabd): Client, GranulabError.

Standard library only (Python >= 3.9). `Client.submit` returns a Job (granulab.jobs), a concurrent.futures.Future
of the job's final status; every method that takes a job takes a Job or its id.
"""

from __future__ import annotations

import json
import os
import socket
import ssl
import time
import urllib.error
import urllib.parse
import urllib.request
from typing import TYPE_CHECKING, Any, Callable, Dict, Iterable, List, Optional, Tuple, Union

from granulab.frames import pandas_module

if TYPE_CHECKING:
    from granulab.jobs import Job
    from granulab.pictures import Picture
    from granulab.sweeps import Sweep

# A spec: a dict, a JSON string, or the path of a JSON file. A job: a Job or its id.
Spec = Union[Dict[str, Any], str, "os.PathLike[str]"]
JobRef = Union[int, "Job"]

__all__ = ["Client", "GranulabError", "DEFAULT_SERVER", "TERMINAL"]

DEFAULT_SERVER = "http://127.0.0.1:8080"
TERMINAL = ("succeeded", "failed", "cancelled")


class GranulabError(Exception):
    """An error reported by the server (status is the HTTP status, 0 if the server is unreachable)."""

    def __init__(self, status: int, code: Optional[str] = "error", message: Optional[str] = "",
                 field: Optional[str] = ""):
        self.status = int(status)
        self.code = code or "error"
        self.message = message or ""
        self.field = field or ""
        super().__init__(str(self))

    def __str__(self) -> str:
        text = f"HTTP {self.status} {self.code}: {self.message}" if self.status else \
            f"{self.code}: {self.message}"
        if self.field:
            text += f" (field '{self.field}')"
        return text




class Client:
    def __init__(self, server: Optional[str] = None, timeout: float = 30.0, token: Optional[str] = None,
                 retries: int = 3, ca_file: Optional[str] = None, poll: float = 0.5):
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
        # poll: seconds between the status requests of the thread that watches this client's Jobs.
        self.poll = float(poll)
        self.watcher = None  # granulab.jobs.Watcher, started with the first Job

    # -- transport -------------------------------------------------------------------------------
    def _request(self, method: str, path: str, query: Optional[Dict[str, Any]] = None, body: Any = None,
                 raw: bool = False, binary: bool = False) -> Any:
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

    def _request_once(self, method: str, path: str, query: Optional[Dict[str, Any]] = None, body: Any = None,
                      raw: bool = False, binary: bool = False) -> Any:
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
    def _error_from(status: int, text: str) -> "GranulabError":
        try:
            err = json.loads(text).get("error") or {}
            if not isinstance(err, dict):
                err = {"message": str(err)}
        except (ValueError, AttributeError):
            err = {"message": text.strip()[:500]}
        return GranulabError(status, err.get("code"), err.get("message"), err.get("field"))

    @staticmethod
    def _spec_body(spec: Spec) -> str:
        if isinstance(spec, dict):
            return json.dumps(spec)
        if isinstance(spec, (str, os.PathLike)) and os.path.exists(spec):
            with open(spec, encoding="utf-8") as f:
                return f.read()
        if isinstance(spec, str) and spec.lstrip().startswith("{"):
            return spec
        raise FileNotFoundError(f"spec file not found: {spec}")

    # -- API ---------------------------------------------------------------------------------------
    def submit(self, spec: Spec, reuse: bool = False, priority: Optional[int] = None) -> "Job":
        """Submit a spec (a dict, a JSON string, or a path to a JSON file). Returns its Job: a
        concurrent.futures.Future whose result() is the job's final status dict (JobFailed if it failed),
        watched by a thread of this client that polls the server (every `poll` s, Client(poll=...))."""
        from granulab.jobs import Job  # jobs imports this module

        return Job(self, self.submit_id(spec, reuse=reuse, priority=priority))

    def submit_id(self, spec: Spec, reuse: bool = False, priority: Optional[int] = None) -> int:
        """Submit a spec; returns the new job's id only (nothing watches it)."""
        body = self._spec_body(spec)
        query = {}
        if reuse:
            query["reuse"] = "true"
        if priority is not None:
            query["priority"] = int(priority)
        return int(self._request("POST", "/v1/jobs", query, body)["id"])

    def dry_run(self, spec: Spec) -> Dict[str, Any]:
        """What a spec would cost on this server, without queueing it: spheres, grains, steps, memory_bytes,
        expected_seconds (at the server's recent speed) and over_budget when it would be refused."""
        return self._request("POST", "/v1/jobs", {"dry_run": "true"}, self._spec_body(spec))

    def status(self, job_id: JobRef) -> Dict[str, Any]:
        return self._request("GET", f"/v1/jobs/{int(job_id)}")

    def wait(self, job_id: JobRef, timeout: Optional[float] = None, poll: float = 0.5,
             on_progress: Optional[Callable[[Dict[str, Any]], None]] = None) -> Dict[str, Any]:
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

    def wait_all(self, job_ids: Iterable[JobRef], timeout: Optional[float] = None, poll: float = 1.0,
                 on_progress: Optional[Callable[[List[Dict[str, Any]]], None]] = None) -> Dict[int, Dict[str, Any]]:
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

    def curve(self, job_id: JobRef) -> Dict[str, Any]:
        """The curve as columns: {"columns": [names], name: [values], ...}; while the job runs, the rows
        computed so far."""
        return self._request("GET", f"/v1/jobs/{int(job_id)}/curve")

    def to_pandas(self, job_id: JobRef) -> Any:
        """The curve as a pandas DataFrame (pandas is never a dependency: ImportError without it)."""
        pandas = pandas_module()  # before the request: ImportError naming what to install
        c = self.curve(job_id)
        return pandas.DataFrame({name: c[name] for name in c["columns"]})

    def snapshot_file(self, job_id: JobRef, k: int, fmt: str = "dump", step: Optional[float] = None) -> str:
        """Snapshot k as text in `fmt`: "dump" (LAMMPS, for OVITO; "dump_spheres": every sphere), "vtk" or
        "vtk_interfaces" (ParaView), "json",
        the contact network "contacts_vtk" or "contacts_dump" (a LAMMPS local dump), the grains' polyhedra "mesh_vtk", or
        the front face's DIC-like map, "dic_csv" or "dic_vtk", on a grid of `step` m (default: half a grain spacing)."""
        query = {"format": fmt}
        if step is not None:
            query["step"] = repr(float(step))
        return self._request("GET", f"/v1/jobs/{int(job_id)}/snapshots/{int(k)}", query, raw=True)

    def archive(self, job_id: JobRef, path: str) -> str:
        """Saves everything of a job (spec, summary, curve, every snapshot in its nine files, all formats but the per-sphere dump_spheres) as a tar at `path`."""
        data = self._request("GET", f"/v1/jobs/{int(job_id)}/archive", raw=True, binary=True)
        with open(path, "wb") as f:
            f.write(data)
        return path

    def curve_csv(self, job_id: JobRef) -> str:
        return self._request("GET", f"/v1/jobs/{int(job_id)}/curve", {"format": "csv"}, raw=True)

    def snapshots(self, job_id: JobRef) -> List[Dict[str, Any]]:
        return self._request("GET", f"/v1/jobs/{int(job_id)}/snapshots").get("snapshots", [])

    def snapshot(self, job_id: JobRef, k: int) -> Dict[str, Any]:
        return self._request("GET", f"/v1/jobs/{int(job_id)}/snapshots/{int(k)}")

    def cancel(self, job_id: JobRef) -> Dict[str, Any]:
        return self._request("POST", f"/v1/jobs/{int(job_id)}/cancel")

    def delete(self, job_id: JobRef) -> Dict[str, Any]:
        """Deletes a finished job with its curve and snapshots (owner or admin)."""
        return self._request("DELETE", f"/v1/jobs/{int(job_id)}")

    def set_priority(self, job_id: JobRef, priority: int) -> Dict[str, Any]:
        """A queued job's new priority, -100..100, higher first (owner or admin)."""
        return self._request("POST", f"/v1/jobs/{int(job_id)}/priority", {"value": int(priority)})

    def list(self, status: Optional[str] = None, limit: int = 50, offset: int = 0,
             owner: Optional[str] = None) -> List[Dict[str, Any]]:
        return self._request("GET", "/v1/jobs", {"status": status, "limit": limit, "offset": offset,
                                                 "owner": owner}).get("jobs", [])

    def submit_sweep(self, spec: Dict[str, Any], vary: Dict[str, List[Any]], mode: str = "product", label: str = "",
                     priority: Optional[int] = None) -> "Sweep":
        """A sweep of `spec` over `vary` ({"dotted.key": [values]}); returns a granulab.Sweep (its jobs as Futures,
        frame(), curves(): granulab.sweeps).

        Each value is the field's value as the spec has it, so a field that is itself a list takes a list per
        point: {"loading.axis": [[1, 1, 0], [1, 1, 1]]} is two jobs, one along each axis (likewise
        "output.snapshot_strains": [[0, 0.01], [0, 0.02]]). mode "zip" pairs the lists (they must be as long as
        each other) instead of running every combination."""
        from granulab.sweeps import Sweep

        sweep_id, job_ids = self.submit_sweep_ids(spec, vary, mode=mode, label=label, priority=priority)
        return Sweep(self, sweep_id, job_ids, spec if isinstance(spec, dict) else {}, dict(vary))

    def submit_sweep_ids(self, spec: Dict[str, Any], vary: Dict[str, List[Any]], mode: str = "product",
                         label: str = "", priority: Optional[int] = None) -> Tuple[int, List[int]]:
        """submit_sweep's request alone: returns (sweep id, [job ids])."""
        body = json.dumps({"spec": spec, "vary": vary, "mode": mode, "label": label})
        r = self._request("POST", "/v1/sweeps", {"priority": priority}, body=body)
        return r["id"], r["jobs"]

    def sweep(self, sweep_id: int) -> Dict[str, Any]:
        """The sweep with its jobs: values, status, progress, first yield and peak."""
        return self._request("GET", f"/v1/sweeps/{int(sweep_id)}")

    def sweeps(self, limit: int = 50, offset: int = 0, owner: Optional[str] = None) -> List[Dict[str, Any]]:
        return self._request("GET", "/v1/sweeps", {"limit": limit, "offset": offset, "owner": owner}).get("sweeps", [])

    def cancel_sweep(self, sweep_id: int) -> Dict[str, Any]:
        return self._request("POST", f"/v1/sweeps/{int(sweep_id)}/cancel")

    def health(self) -> Dict[str, Any]:
        return self._request("GET", "/v1/health")

    def experiments(self) -> List[Dict[str, Any]]:
        """Every experiment the server runs: its spec fields (default, range, unit), curve columns and headline."""
        return self._request("GET", "/v1/experiments").get("experiments", [])

    def experiment(self, name: str) -> Dict[str, Any]:
        """One experiment's entry of GET /v1/experiments (fields, curve columns, headline), asked once per client
        (a server's experiments do not change while it runs). KeyError for a name the server does not run."""
        cache = self.__dict__.setdefault("_experiments", {})
        if name not in cache:
            for e in self.experiments():
                cache[e.get("name")] = e
        if name not in cache:
            raise KeyError(f"the server runs no experiment named {name!r}")
        return cache[name]

    def headline(self, experiment: str) -> Dict[str, Any]:
        """What `experiment` (its name) shows first, as GET /v1/experiments has it: its key values' labels, units
        and summary paths among them (for key_values()). KeyError for a name the server does not run."""
        return self.experiment(experiment)["headline"]

    def field_defaults(self, experiment: str) -> Dict[str, Any]:
        """{dotted spec field: its default} of an experiment."""
        return {f["field"]: f.get("default") for f in self.experiment(experiment).get("fields", [])}

    def picture(self, path: str, **query: Any) -> "Picture":
        """An SVG the server draws (the routes ending in .svg), as a Picture: a str that a notebook shows inline."""
        from granulab.pictures import Picture

        return Picture(self._request("GET", path, {k: v for k, v in query.items() if v is not None}, raw=True))
