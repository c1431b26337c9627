"""A sweep on the server as an object: its jobs as Futures, one table of them, their curves in one long table.

    sweep = client.submit_sweep(spec, {"loading.confining_pressure": [10e3, 30e3, 60e3]})
    sweep.wait()                          # one progress display
    sweep.frame()                         # a row per job: confining_pressure, status, first yield, peak...
    sweep.curves(units="natural")         # every job's curve, a row per curve point, in p0 and %
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Dict, List, Optional

from granulab.frames import Columns, plain_name, to_frame
from granulab.headline import dotted
from granulab.jobs import Job
from granulab.progress import wait

if TYPE_CHECKING:
    from granulab.client import Client

__all__ = ["Sweep"]


class Sweep:
    def __init__(self, client: "Client", sweep_id: int, job_ids: List[int], spec: Dict[str, Any],
                 vary: Dict[str, List[Any]]):
        self.client = client
        self.id = int(sweep_id)
        self.jobs: List[Job] = [Job(client, i) for i in job_ids]
        self.spec = spec
        self.vary = vary
        self.experiment = spec.get("experiment", "crystal_compression")

    def __repr__(self) -> str:
        done = sum(1 for j in self.jobs if j.done())
        return f"<Sweep {self.id}: {done}/{len(self.jobs)} jobs done, varying {', '.join(self.vary)}>"

    def info(self) -> Dict[str, Any]:
        """GET /v1/sweeps/{id}: its spec, vary, counts by status and each job's values, status and key values."""
        return self.client.sweep(self.id)

    def wait(self, timeout: Optional[float] = None, progress: bool = True) -> "Sweep":
        wait(self.jobs, timeout=timeout, progress=progress)
        return self

    def cancel(self) -> Dict[str, Any]:
        return self.client.cancel_sweep(self.id)

    def _varied(self, item: Dict[str, Any]) -> Dict[str, Any]:
        """A job's point as plain columns; a list value (an axis) as a tuple, so that it can be grouped on."""
        keys = list(self.vary)
        values = item.get("values") or {}
        out = {}
        for k in keys:
            v = values.get(k)
            out[plain_name(k, keys)] = tuple(v) if isinstance(v, list) else v
        return out

    def rows(self) -> Columns:
        """The sweep's table as plain columns, one row per job: `job`, each varied field (its last name part, e.g.
        `confining_pressure`), `status`, `progress`, and the headline's key values as `granulab sweep`'s
        sweep.csv names them: the dotted summary path with "_" for "." (`first_yield_deviator_over_p0`, with
        `first_yield_strain` and `first_yield_deviator` where it sits on the curve, SI), and for a value that may
        not exist `<group>_found` and `<group>_reason` (its numbers then None)."""
        headline = self.client.headline(self.experiment)
        items = self.info().get("jobs", [])
        columns: Columns = {"job": []}
        order: List[str] = ["job"]

        def put(row_index: int, name: str, value: Any) -> None:
            if name not in columns:
                columns[name] = [None] * row_index
                order.append(name)
            columns[name].append(value)

        for n, item in enumerate(items):
            columns["job"].append(int(item["id"]))
            for name, value in self._varied(item).items():
                put(n, name, value)
            put(n, "status", item.get("status"))
            put(n, "progress", item.get("progress"))
            for v in headline.get("values", []):
                group_path = v.get("status")
                group = dotted(item, group_path) if group_path else None
                if group_path:
                    base = group_path.replace(".", "_")
                    found = group.get("found") if isinstance(group, dict) else None
                    put(n, base + "_found", found)
                    reason = group.get("reason") if isinstance(group, dict) else None
                    put(n, base + "_reason", reason if found is False else None)
                for path in (v["key"], v.get("at_x"), v.get("at_y")):
                    if path:
                        number = dotted(item, path)
                        put(n, path.replace(".", "_"),
                            number if isinstance(number, (int, float)) and not isinstance(number, bool) else None)
            for name in order:  # a column this row did not reach
                if len(columns[name]) < n + 1:
                    columns[name].append(None)
        return {name: columns[name] for name in order}

    def frame(self):
        """rows() as a pandas DataFrame (one row per job)."""
        return to_frame(self.rows())

    def curve_rows(self, units: str = "natural") -> Columns:
        """Every job's curve as its headline draws it (x and each series, `units` "natural" or "si"), stacked:
        `job`, the varied fields, then the curve's columns; the jobs that have no curve rows yet add none."""
        return self._curve_table(units)[0]

    def curves(self, units: str = "natural"):
        """curve_rows() as one long pandas DataFrame; attrs["units"] gives each curve column's unit."""
        return to_frame(*self._curve_table(units))

    def _curve_table(self, units: str):
        """(curve_rows' columns, {curve column: unit})."""
        items = {int(i["id"]): i for i in self.info().get("jobs", [])}
        out: Columns = {}
        units_of: Dict[str, str] = {}
        for job in self.jobs:
            cols, units_of = job.curve_rows(units)
            n = len(next(iter(cols.values()))) if cols else 0
            point = self._varied(items.get(job.id, {}))
            for name, value in [("job", job.id)] + list(point.items()):
                out.setdefault(name, []).extend([value] * n)
            for name, values in cols.items():
                out.setdefault(name, []).extend(values)
        return out, units_of

    def curves_svg(self, units: str = "natural", y: Optional[str] = None):
        """The server's picture of the sweep's curves overlaid (shown inline in a notebook)."""
        return self.client.picture(f"/v1/sweeps/{self.id}/curves.svg", units=units, y=y)
