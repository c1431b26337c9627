"""Tables of results: a job's curve in the experiment's natural or SI units (from its headline), a snapshot's
grains, interfaces and contacts, a sweep's jobs. Each comes as plain columns ({name: [values]}, standard library)
and as a pandas DataFrame when pandas is installed (the `pandas` extra; Debian: python3-pandas)."""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Tuple

from granulab.headline import dotted

__all__ = ["pandas_module", "to_frame", "headline_columns", "snapshot_columns", "plain_name"]

Columns = Dict[str, List[Any]]


def pandas_module():
    """pandas, or ImportError saying what to install."""
    try:
        import pandas
    except ImportError:
        raise ImportError("DataFrames need pandas: pip install './clients/python[pandas]' (Debian: python3-pandas); "
                          "the same tables come as plain columns without it") from None
    return pandas


def to_frame(columns: Columns, units: Optional[Dict[str, str]] = None):
    """A DataFrame of plain columns; `units` ({column: unit}) kept in its attrs["units"]."""
    frame = pandas_module().DataFrame(columns)
    if units:
        frame.attrs["units"] = dict(units)
    return frame


def _scale(scale: Dict[str, Any], spec: Dict[str, Any], defaults: Dict[str, Any]) -> Tuple[float, str]:
    """The factor a stored (SI) value is multiplied by in the headline scale {"factor", "unit", "per_field"}."""
    factor = float(scale.get("factor", 1.0))
    per_field = scale.get("per_field")
    if per_field:
        per = dotted(spec, per_field)
        if per is None:
            per = defaults.get(per_field)
        if not isinstance(per, (int, float)) or per == 0:
            raise ValueError(f"the headline's scale is per {per_field}, which the job's spec does not give")
        factor /= float(per)
    return factor, str(scale.get("unit", ""))


def headline_columns(curve: Dict[str, Any], headline: Dict[str, Any], spec: Dict[str, Any],
                     defaults: Dict[str, Any], units: str = "natural") -> Tuple[Columns, Dict[str, str]]:
    """A curve (GET /v1/jobs/{id}/curve) as its headline draws it: the x column and each series in `units`
    ("natural": e.g. a crystal's stresses in p0 against strain in %; "si": kPa against %), named by their curve
    columns (the natural or SI column of each series). Returns (columns, {column: unit})."""
    if units not in ("natural", "si"):
        raise ValueError("units: 'natural' or 'si'")
    x = headline["x"]
    fx, ux = _scale(x[units], spec, defaults)
    fy, uy = _scale(headline["y"][units], spec, defaults)
    out: Columns = {x["column"]: [v * fx for v in curve[x["column"]]]}
    unit_of = {x["column"]: ux}
    for series in headline["series"]:
        name = series["column"] if units == "natural" else series.get("si_column") or series["column"]
        if name in curve and name not in out:
            out[name] = [v * fy for v in curve[name]]
            unit_of[name] = uy
    return out, unit_of


# Columns of a snapshot's sections that hold grain indices: integers, whatever the JSON wrote.
_INDEX_COLUMNS = ("id", "a", "b", "grain", "grain_a", "grain_b")


def snapshot_columns(snapshot: Dict[str, Any], section: str = "grains") -> Columns:
    """One section of a snapshot's JSON (GET /v1/jobs/{id}/snapshots/{k}): "grains" (one row per grain: pose,
    displacement, local strains...), "interfaces" (grain pairs sharing a face: their sliding) or
    "contact_network" (grain pairs in contact: forces). Grain indices as integers."""
    table = snapshot.get(section)
    if not isinstance(table, dict):
        have = [k for k, v in snapshot.items() if isinstance(v, dict) and all(isinstance(c, list) for c in v.values())]
        raise KeyError(f"the snapshot has no section {section!r} (it has {', '.join(have)})")
    out: Columns = {}
    for name, values in table.items():
        if not isinstance(values, list):
            continue
        out[name] = [int(v) for v in values] if name in _INDEX_COLUMNS else list(values)
    return out


def plain_name(dotted_key: str, others: List[str]) -> str:
    """A varied spec field as a plain column name: its last part ("confining_pressure") unless another varied
    field ends the same, then the whole path with "_" for "." ("loading_confining_pressure")."""
    last = dotted_key.split(".")[-1]
    if sum(1 for k in others if k.split(".")[-1] == last) > 1:
        return dotted_key.replace(".", "_")
    return last
