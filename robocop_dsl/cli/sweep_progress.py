"""The progress of ``sweep``: jobs done, the running success rate, the count of each
outcome, the time elapsed and an estimate of the time left (ETA).

On a terminal it is a bar (rich) redrawn as jobs finish; elsewhere (a pipe, a CI log)
it is one line every ``every`` jobs and one at the end, e.g.::

    20/50 jobs  success rate 85.0 %  failure 3  success 17  elapsed 0:00:12  ETA 0:00:18

The estimate is the mean wall time per finished job so far times the jobs left.
"""

from __future__ import annotations

import sys
import time
from collections import Counter
from datetime import timedelta

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn

LINES = 10
"""Lines printed over a sweep when not on a terminal (plus the last one)."""


class SweepProgress:
    """Progress of a sweep of ``total`` jobs, written to ``stream`` (standard error).

    Args:
        total: Jobs the sweep runs.
        stream: Where to write; standard error by default.
        every: Jobs between two lines when not on a terminal; default a tenth of
            ``total``.
    """

    def __init__(self, total: int, stream=None, every: int | None = None):
        self.console = Console(file=stream or sys.stderr, highlight=False)
        self.total = total
        self.every = every or max(total // LINES, 1)
        self.counts: Counter = Counter()
        self._progress = None
        self._task = None
        self._started = time.perf_counter()

    def __enter__(self) -> "SweepProgress":
        self._started = time.perf_counter()
        if self.console.is_terminal:
            self._progress = Progress(
                TextColumn("jobs"), BarColumn(bar_width=20), MofNCompleteColumn(),
                TextColumn("{task.fields[rate]}"), TextColumn("{task.description}"),
                TextColumn("{task.fields[times]}"), console=self.console)
            self._progress.start()
            self._task = self._progress.add_task("", total=self.total, rate="", times="")
        return self

    def __exit__(self, *exc) -> None:
        if self._progress is not None:
            self._progress.stop()

    @property
    def done(self) -> int:
        return sum(self.counts.values())

    def rate(self) -> str:
        """The share of finished jobs that succeeded, e.g. ``success rate 85.0 %``."""
        return f"success rate {100 * self.counts['success'] / max(self.done, 1):.1f} %"

    def times(self) -> str:
        """``elapsed H:MM:SS  ETA H:MM:SS``."""
        elapsed = time.perf_counter() - self._started
        left = elapsed / max(self.done, 1) * (self.total - self.done)
        return f"elapsed {_clock(elapsed)}  ETA {_clock(left)}"

    def update(self, row: dict) -> None:
        """Count the finished job of ``row`` and show the progress."""
        self.counts[row["outcome"]] += 1
        done = self.done
        text = "  ".join(f"{o} {n}" for o, n in sorted(self.counts.items()))
        if self._progress is not None:
            self._progress.update(self._task, completed=done, description=text,
                                  rate=self.rate(), times=self.times())
        elif done % self.every == 0 or done == self.total:
            self.console.print(f"{done}/{self.total} jobs  {self.rate()}  {text}  "
                               f"{self.times()}", soft_wrap=True)


def _clock(seconds: float) -> str:
    """``seconds`` as ``H:MM:SS``."""
    return str(timedelta(seconds=round(seconds)))
