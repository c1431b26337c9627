"""Waiting for jobs with a progress display: tqdm's bar when tqdm is installed (tqdm.auto: a widget in a notebook),
else one line on stderr rewritten in place (a new line per change where stderr is not a terminal, as in a notebook's
output or a log)."""

from __future__ import annotations

import concurrent.futures
import sys
import time
from typing import Iterable, List, Optional

from granulab.jobs import Job

__all__ = ["wait"]


class _Line:
    """The plain display: "3/8 jobs done, 41.2 %" on stderr."""

    def __init__(self, total: int):
        self.total = total
        self.tty = sys.stderr.isatty()
        self.shown = ""

    def update(self, fraction: float, done: int) -> None:
        text = f"{done}/{self.total} job{'s' if self.total != 1 else ''} done, {100 * fraction / self.total:.1f} %"
        if text == self.shown:
            return
        self.shown = text
        sys.stderr.write(("\r" + text) if self.tty else (text + "\n"))
        sys.stderr.flush()

    def close(self) -> None:
        if self.tty and self.shown:
            sys.stderr.write("\n")


class _Bar:
    """tqdm's bar over the jobs' summed fractions done."""

    def __init__(self, total: int, tqdm):
        self.bar = tqdm(total=float(total), unit="job", bar_format="{l_bar}{bar}| {n:.2f}/{total:.0f} jobs "
                        "[{elapsed}<{remaining}]")
        self.last = 0.0

    def update(self, fraction: float, done: int) -> None:
        if fraction > self.last:
            self.bar.update(fraction - self.last)
            self.last = fraction
        self.bar.set_postfix_str(f"{done} done", refresh=False)

    def close(self) -> None:
        self.bar.close()


def _display(total: int):
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return _Line(total)
    return _Bar(total, tqdm)


def wait(jobs: Iterable[Job], timeout: Optional[float] = None, progress: bool = True,
         every: float = 0.5) -> List[Job]:
    """Waits until every job has ended (succeeded, failed or cancelled), showing their progress; returns the jobs.
    TimeoutError if `timeout` seconds pass first (the jobs go on on the server). Their outcomes: job.result()."""
    jobs = list(jobs)
    display = _display(len(jobs)) if progress and jobs else None
    deadline = None if timeout is None else time.monotonic() + timeout
    try:
        while True:
            left = None if deadline is None else deadline - time.monotonic()
            step = every if left is None else max(0.0, min(every, left))
            _, pending = concurrent.futures.wait(jobs, timeout=step)
            if display is not None:
                display.update(sum(1.0 if j.done() else j.progress for j in jobs), len(jobs) - len(pending))
            if not pending:
                return jobs
            if deadline is not None and time.monotonic() >= deadline:
                raise TimeoutError(f"{len(pending)} of {len(jobs)} jobs still running after {timeout} s")
    finally:
        if display is not None:
            display.close()
