"""A job on the server as a concurrent.futures.Future, and the thread that watches a client's jobs.

    import concurrent.futures
    jobs = [client.submit(spec) for spec in specs]
    for job in concurrent.futures.as_completed(jobs):   # in the order they finish
        print(job.id, job.result()["summary"]["peak"])

result() is the job's final status dict (GET /v1/jobs/{id}: "summary" and all); a failed job raises JobFailed (its
message is the server's), a job cancelled on the server raises concurrent.futures.CancelledError. Callbacks added
with add_done_callback() run on the watching thread. Standard library only.
"""

from __future__ import annotations

import concurrent.futures
import threading
import time
from typing import TYPE_CHECKING, Any, Dict, List, Optional

from granulab.client import TERMINAL, GranulabError

if TYPE_CHECKING:
    from granulab.client import Client

__all__ = ["Job", "JobFailed", "Watcher"]


class JobFailed(GranulabError):
    """A job that ended "failed" on the server: the server's message; its last status dict in `status_dict`."""

    def __init__(self, job_id: int, status_dict: Dict[str, Any]):
        message = status_dict.get("error") or f"job {job_id} failed"
        if isinstance(message, dict):
            message = message.get("message", str(message))
        super().__init__(0, "failed", f"job {job_id}: {message}")
        self.job_id = job_id
        self.status_dict = status_dict


class Job(concurrent.futures.Future):
    """A submitted job: a Future of its final status dict, with the server's view of it at hand."""

    def __init__(self, client: "Client", job_id: int):
        super().__init__()
        self.client = client
        self.id = int(job_id)
        self.last: Optional[Dict[str, Any]] = None  # the last status dict seen (the watcher's or status()'s)
        client_watcher(client).add(self)

    def __int__(self) -> int:
        return self.id

    __index__ = __int__

    def __repr__(self) -> str:
        state = (self.last or {}).get("status", "submitted")
        return f"<Job {self.id} {state} {100 * self.progress:.0f} %>"

    @property
    def progress(self) -> float:
        """The fraction done (0..1) as last seen; 1 once it succeeded."""
        st = self.last or {}
        if st.get("status") == "succeeded":
            return 1.0
        p = st.get("progress")
        return float(p) if isinstance(p, (int, float)) else 0.0

    def status(self) -> Dict[str, Any]:
        """The job's status now (one request); completes the Future if the job has ended."""
        st = self.client.status(self.id)
        self.observe(st)
        return st

    def curve(self) -> Dict[str, Any]:
        """The curve as columns ({"columns": [...], name: [...]}); while it runs, the rows so far."""
        return self.client.curve(self.id)

    def snapshots(self) -> List[Dict[str, Any]]:
        return self.client.snapshots(self.id)

    def curve_rows(self, units: Optional[str] = None):
        """The curve as plain columns: every column as stored (SI) with units None, or the headline's x and series
        in `units` "natural" or "si" (granulab.frames.headline_columns). Returns (columns, {column: unit})."""
        from granulab.frames import headline_columns

        curve = self.curve()
        experiment = self.client.experiment((self.last or self.status())["experiment"])
        if units is None:
            unit_of = {c["name"]: c["unit"] for c in experiment.get("curve_columns", [])}
            return {name: curve[name] for name in curve["columns"]}, unit_of
        spec = (self.last or {}).get("spec") or self.status().get("spec") or {}
        defaults = self.client.field_defaults(experiment["name"])
        return headline_columns(curve, experiment["headline"], spec, defaults, units)

    def frame(self, units: Optional[str] = None):
        """The curve as a pandas DataFrame (curve_rows); attrs["units"] gives each column's unit."""
        from granulab.frames import to_frame

        return to_frame(*self.curve_rows(units))

    def snapshot_frame(self, k: int, section: str = "grains"):
        """Snapshot k's "grains", "interfaces" or "contact_network" as a pandas DataFrame, one row per grain or
        grain pair (granulab.frames.snapshot_columns)."""
        from granulab.frames import snapshot_columns, to_frame

        return to_frame(snapshot_columns(self.client.snapshot(self.id, k), section))

    def write_gsd(self, path: str) -> str:
        """The snapshots as a GSD trajectory with each grain's sphere union as its shape (granulab.gsd_file; needs
        gsd): OVITO draws the grains."""
        from granulab.gsd_file import write_gsd

        return write_gsd(self, path)

    def curve_svg(self, units: str = "natural", y: Optional[str] = None):
        """The server's picture of the curve (shown inline in a notebook)."""
        return self.client.picture(f"/v1/jobs/{self.id}/curve.svg", units=units, y=y)

    def snapshot_svg(self, k: int, field: Optional[str] = None, slice: Optional[int] = None):
        """Snapshot k's section through the crystal, coloured by `field` (docs/api.md, "Pictures")."""
        return self.client.picture(f"/v1/jobs/{self.id}/snapshots/{int(k)}.svg", field=field, slice=slice)

    def dic_svg(self, k: int, field: Optional[str] = None, step: Optional[float] = None):
        """Snapshot k's DIC-like map of the front face."""
        return self.client.picture(f"/v1/jobs/{self.id}/snapshots/{int(k)}/dic.svg", field=field, step=step)

    def wait(self, timeout: Optional[float] = None, progress: bool = True) -> Dict[str, Any]:
        """Waits with a progress display (granulab.wait) and returns result()."""
        from granulab.progress import wait

        wait([self], timeout=timeout, progress=progress)
        return self.result()

    def cancel(self) -> bool:
        """Asks the server to cancel the job; True if it was cancelled (result() then raises CancelledError),
        False if it had already ended or the server refused (the refusal is in `last_error`)."""
        if self.done():
            return False
        try:
            self.client.cancel(self.id)
        except GranulabError as e:
            self.last_error = e
            self.status()  # it may have ended meanwhile
            return False
        return super().cancel()

    def observe(self, st: Dict[str, Any]) -> None:
        """Takes a status dict of this job: completes the Future when it says the job ended."""
        self.last = st
        state = st.get("status")
        if state not in TERMINAL:
            return
        try:
            if state == "succeeded":
                self.set_result(st)
            elif state == "failed":
                self.set_exception(JobFailed(self.id, st))
            else:  # cancelled on the server (by this client, a sweep's cancel, or an admin)
                super().cancel()
        except concurrent.futures.InvalidStateError:
            pass  # completed already, by the other observer


class Watcher:
    """Polls the server for a client's unfinished Jobs on one daemon thread, which ends when none is left (and
    starts again with the next). Every `client.poll` s, and no more than 20 requests a second for many jobs."""

    def __init__(self, client: "Client"):
        self.client = client
        self.lock = threading.Lock()
        self.jobs: Dict[int, Job] = {}
        self.thread: Optional[threading.Thread] = None

    def add(self, job: Job) -> None:
        with self.lock:
            self.jobs[job.id] = job
            if self.thread is None:
                self.thread = threading.Thread(target=self.run, name=f"granulab-watch-{id(self)}", daemon=True)
                self.thread.start()

    def run(self) -> None:
        while True:
            with self.lock:
                for i in [i for i, j in self.jobs.items() if j.done()]:
                    del self.jobs[i]
                pending = list(self.jobs.values())
                if not pending:
                    self.thread = None
                    return
            for job in pending:
                try:
                    job.observe(self.client.status(job.id))
                except GranulabError as e:
                    if e.status == 404:  # deleted on the server: it will never end
                        try:
                            job.set_exception(e)
                        except concurrent.futures.InvalidStateError:
                            pass
                    # anything else (a restarting server): asked again at the next round
            time.sleep(max(self.client.poll, 0.05 * len(pending)))


_watchers_lock = threading.Lock()


def client_watcher(client: "Client") -> Watcher:
    with _watchers_lock:
        if client.watcher is None:
            client.watcher = Watcher(client)
        return client.watcher
