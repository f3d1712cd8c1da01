"""The progress of ``sweep``: a bar with the count of each outcome."""

from __future__ import annotations

import sys
from collections import Counter

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, \
    TimeElapsedColumn


class SweepProgress:
    """A progress bar with the count of each outcome (a line per tenth when not on a
    terminal)."""

    def __init__(self, total: int, stream=None):
        self.console = Console(file=stream or sys.stderr, highlight=False)
        self.total = total
        self.counts: Counter = Counter()
        self._progress = None
        self._task = None

    def __enter__(self) -> "SweepProgress":
        if self.console.is_terminal:
            self._progress = Progress(TextColumn("jobs"), BarColumn(), MofNCompleteColumn(),
                                      TimeElapsedColumn(), TextColumn("{task.description}"),
                                      console=self.console)
            self._progress.start()
            self._task = self._progress.add_task("", total=self.total)
        return self

    def __exit__(self, *exc) -> None:
        if self._progress is not None:
            self._progress.stop()

    def update(self, row: dict) -> None:
        self.counts[row["outcome"]] += 1
        done = sum(self.counts.values())
        text = "  ".join(f"{o} {n}" for o, n in sorted(self.counts.items()))
        if self._progress is not None:
            self._progress.update(self._task, completed=done, description=text)
        elif done * 10 // self.total != (done - 1) * 10 // self.total or done == self.total:
            self.console.print(f"{done}/{self.total} jobs  {text}")
