"""Observers a campaign adds to every run: what the results table reports about the
run, and the job's wall-time budget."""

from __future__ import annotations

import math
import time

import numpy as np

from ..diagnostics import RobocopError
from ..runtime.records import Observer


class BudgetExceeded(RobocopError):
    """A job ran past its wall-time budget.

    Attributes:
        budget: The budget [s].
    """

    def __init__(self, budget: float):
        self.budget = budget
        super().__init__(f"ran past its time budget of {budget:g} s")


class Budget(Observer):
    """Ends a job once the wall time since ``started`` (a ``time.perf_counter()``
    reading) exceeds ``seconds``: :meth:`check` raises :class:`BudgetExceeded` before
    the run, and during it the run is stopped (the robot brought to rest) with
    :attr:`exceeded` set."""

    wants_tasks = False

    def __init__(self, seconds: float | None, started: float):
        self.seconds = seconds
        self.deadline = math.inf if seconds is None else started + seconds
        self.exceeded: BudgetExceeded | None = None
        self._runner = None

    def expire(self) -> None:
        """End the budget now: the run stops at its next cycle."""
        self.deadline = -math.inf

    def check(self) -> None:
        if time.perf_counter() > self.deadline:
            raise BudgetExceeded(self.seconds)

    def on_start(self, runner) -> None:
        self._runner = runner

    def on_cycle(self, record) -> None:
        if self.exceeded is None and time.perf_counter() > self.deadline:
            self.exceeded = BudgetExceeded(self.seconds)
            self._runner.stop(str(self.exceeded), "stopped")


RESOLUTION = 9
"""Decimals kept of measured errors and margins (1e-9 m or rad): finer digits are below
the QP tolerance and differ between runs of the same job (ProxQP's results vary in
their last bits with memory layout), so that equal campaigns give equal tables."""


class Probe(Observer):
    """Follows a run for the results table: the smallest joint-limit margin over the run
    and the largest task error in its last cycle."""

    wants_tasks = False

    def __init__(self):
        self.margin = math.inf
        self.limit_joint = ""
        self.cycles = 0
        self.tasks: tuple = ()
        self._lower = self._upper = None
        self._names: list = []
        self._runner = None

    def on_start(self, runner) -> None:
        self._runner = runner
        group = runner.controller.joint_group
        self._lower, self._upper = np.asarray(group.lower), np.asarray(group.upper)
        self._names = list(runner.joint_names)

    def on_cycle(self, record) -> None:
        margins = np.minimum(record.positions - self._lower, self._upper - record.positions)
        if margins.size:
            index = int(np.argmin(margins))
            if margins[index] < self.margin:
                self.margin = float(margins[index])
                self.limit_joint = self._names[index]
        self.cycles += 1

    def on_stop(self, result) -> None:
        self.tasks = self._runner.task_views()

    def fields(self) -> dict:
        """``worst_task_error`` [m or rad] (NaN when no task was enabled at the end),
        ``min_limit_margin`` [rad or m] (NaN before the first cycle, inf without limits)
        and ``limit_joint``, the joint that came closest."""
        errors = [task.error for task in self.tasks]
        worst = float(max(errors)) if errors else math.nan
        margin = self.margin if self.cycles else math.nan
        return {"worst_task_error": round(worst, RESOLUTION),
                "min_limit_margin": round(margin, RESOLUTION), "limit_joint": self.limit_joint}
