"""A job's key values as its experiment's headline names them (what the web page and `granulab wait` show)."""

from __future__ import annotations

import collections
from typing import Any, Dict, List

__all__ = ["KeyValue", "key_values", "dotted"]

KeyValue = collections.namedtuple("KeyValue", "label value unit reason")
KeyValue.__doc__ = """One key value of a job: its label, its number (None when there is none), its unit, and the
reason there is none when the job's summary says it was not found (else None)."""


def dotted(obj: Any, path: str) -> Any:
    """The value at a dotted path of nested dicts ("first_yield.strain"), or None."""
    for key in path.split("."):
        if not isinstance(obj, dict):
            return None
        obj = obj.get(key)
    return obj


def key_values(item: Dict[str, Any], headline: Dict[str, Any]) -> List[KeyValue]:
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
        group = dotted(summary, v["status"]) if v.get("status") else None
        if isinstance(group, dict) and group.get("found") is False:
            reason = group.get("reason")
            values.append(KeyValue(v["label"], None, v["unit"], reason if isinstance(reason, str) else "none"))
            continue
        number = dotted(summary, v["key"])
        found = isinstance(number, (int, float)) and not isinstance(number, bool)
        values.append(KeyValue(v["label"], number if found else None, v["unit"], None))
    return values
