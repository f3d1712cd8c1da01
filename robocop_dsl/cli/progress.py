"""Terminal output of ``run``: a live line (rich) with mission time and the active
configuration, plain transition lines (full state paths) when not a terminal, and the
end-of-run summary.

In a real-time run the lines are printed by a thread of their own while the loop
sleeps between two cycles (:mod:`~robocop_dsl.runtime.writer_thread`): a slow or
blocked terminal never holds the loop up, and no line is dropped."""

from __future__ import annotations

import math
import sys
import time

import numpy as np
from rich.console import Console
from rich.table import Table

from ..runtime.records import Observer
from ..runtime.writer_thread import DROP, WAIT, WriterThread
from ..safety.report import EXCESS_UNITS

REFRESH = 0.1
BACKLOG = 16
"""Batches of lines waiting for the printing thread before they are merged into one
(none is dropped)."""


class ProgressDisplay(Observer):
    """Shows mission time and the active configuration; refreshes at most every 0.1 s of
    wall time.

    Args:
        mission_name: Shown on every status line.
        stream: Where to write (standard error by default).
        realtime: The run is in real time: lines are printed by a thread of their own,
            while the loop sleeps; else at once, in the loop's thread. :meth:`close`
            prints what is left.
    """

    wants_tasks = False

    def __init__(self, mission_name: str, stream=None, realtime: bool = False):
        stream = stream or sys.stderr
        self.console = Console(file=stream, width=None if stream.isatty() else 120)
        self.mission_name = mission_name
        self.live = self.console.is_terminal
        self._status = None
        self._last = 0.0
        self._relaxed: set[str] = set()
        self._runner = None
        self._realtime = realtime
        self._lines = WriterThread("run output", self._print, BACKLOG,
                                   DROP if realtime else WAIT, keep=list)

    def on_start(self, runner) -> None:
        self._runner = runner
        if self.live:
            self._status = self.console.status(f"{self.mission_name}: starting")
            self._status.start()
        else:       # before the first cycle, so at once (rich's first print is its slowest)
            self.console.print(f"{self.mission_name}: start in {runner.state}", highlight=False)

    def on_cycle(self, record) -> None:
        if self._realtime:
            self._lines.loop_sleeps(self._runner.next_cycle_at)
        if self._status is None:
            return
        now = time.perf_counter()
        if now - self._last >= REFRESH:
            self._last = now
            self._status.update(f"{self.mission_name}: {record.time:8.3f} s  [bold]{record.state}")

    def on_event(self, event) -> None:
        text = self._line(event)
        if text is not None:
            self._lines.put([text])

    def _line(self, event) -> str | None:
        """The line an event prints, or ``None``."""
        if event.kind == "transition":
            return (f"{event.time:8.3f} s  {event.data['from']} -> {event.data['to']}"
                    f"  ({event.data['condition']})")
        if event.kind == "event":
            return f"{event.time:8.3f} s  event: {event.data['name']}"
        if event.kind == "constraint_relaxed":
            name = event.data["constraint"]
            if name in self._relaxed:
                return None
            self._relaxed.add(name)
            return (f"{event.time:8.3f} s  constraint_relaxed: {name} by "
                    f"{event.data['amount']:.4g} {event.data['unit']} (rows "
                    f"{', '.join(map(str, event.data['rows']))}; later ones in the log)")
        if event.kind in ("fault", "qp_failure", "overrun", "log", "solver_budget"):
            if event.kind == "qp_failure" and event.data.get("repeat"):
                return None
            return f"{event.time:8.3f} s  {event.kind}: {event.data.get('message', '')}"
        return None

    def _print(self, lines: list) -> None:
        """In the printing thread (or the caller's, headless): each line, while the
        loop sleeps."""
        for line in lines:
            self._lines.turn()
            self.console.print(line, highlight=False)

    def close(self) -> None:
        """Print the lines still waiting, then stop the live status line."""
        self._lines.close()
        if self._status is not None:
            self._status.stop()
            self._status = None


def print_summary(result, stream, explained=None) -> None:
    """Outcome, final state, transitions with times and conditions, cycle timings, and
    ``explained`` (a :class:`~robocop_dsl.runtime.summary.RunSummary`): the enabled
    tasks' final errors and, for a run that did not succeed, why."""
    console = Console(file=stream, highlight=False,
                      width=None if stream.isatty() else 120)
    colour = {"success": "green", "failure": "red", "fault": "red"}.get(result.outcome, "yellow")
    console.print(f"outcome: [{colour}]{result.outcome}[/]  final state: {result.final_state}"
                  f"  mission time: {result.mission_time:.3f} s")
    if result.message:
        console.print(f"reason: {result.message}")
    table = Table(title="transitions", show_edge=False)
    for column in ("time [s]", "from", "to", "condition"):
        table.add_column(column)
    for transition in result.transitions:
        table.add_row(f"{transition.time:.3f}", transition.source, transition.target,
                      transition.condition)
    console.print(table)
    times = np.asarray(result.cycle_times) * 1e3
    if len(times):
        console.print(f"cycles: {result.cycles}  cycle time median {np.median(times):.3f} ms"
                      f"  p99 {np.percentile(times, 99):.3f} ms  max {times.max():.3f} ms"
                      f"  QP failures: {result.qp_failures}  overruns: {result.overruns}")
    console.print(safety_text(result.safety))
    if explained is not None:
        print_explanation(explained, console)


def safety_text(report) -> str:
    """One line: whether every promise held, each collision constraint's smallest
    clearance, the excesses over limits and the relaxed cycles."""
    parts = ["safety: " + ("[green]every promise held[/]" if report.held
                           else "[red]a promise was broken[/]")]
    for label, clearance in report.clearances.items():
        measured = (f"{clearance * 1e3:.1f} mm" if math.isfinite(clearance)
                    else "never within influence")
        parts.append(f"smallest clearance of {label}: {measured} (min_distance "
                     f"{report.min_distances[label] * 1e3:g} mm)")
    excesses = [f"{kind} {value:.4g} {EXCESS_UNITS[kind]} ({report.excess_at[kind]})"
                for kind, value in report.excess.items() if value]
    parts.append("excess over limits: " + (", ".join(excesses) if excesses else "none"))
    if report.relaxed:
        parts.append("relaxed cycles: " + ", ".join(f"{name} {count}"
                                                    for name, count in report.relaxed.items()))
    if report.budget_cycles:
        parts.append(f"solver budget spent: {report.budget_cycles} cycles")
    return "\n  ".join(parts)


def print_explanation(summary, console: Console) -> None:
    """The tasks table, then the clauses that fired or were waiting, each elementary
    condition with what it measured."""
    table = Table(title="tasks at the end", show_edge=False)
    for column in ("task", "type", "body or group", "error", "reached"):
        table.add_column(column)
    for task in summary.tasks:
        table.add_row(task.name, task.kind, task.target, task.error_text(),
                      "[green]yes[/]" if task.reached else "[red]no[/]")
    if summary.tasks:
        console.print(table)
    else:
        console.print("tasks at the end: none enabled")
    for firing in summary.fired:
        console.print(f"fired at {firing.time:.3f} s: {firing.source} -> {firing.target}"
                      f"  ({firing.condition})")
        _print_clauses(console, firing.others, f"the other clauses of {firing.source}")
    if summary.pending:
        _print_clauses(console, summary.pending, "waiting at the end")


def _print_clauses(console: Console, clauses, title: str) -> None:
    if not clauses:
        return
    console.print(f"  {title}:")
    for clause in clauses:
        console.print(f"    {clause.state}: when {clause.text} -> {clause.target}")
        for atom in clause.atoms:
            mark = "[green]holds[/]" if atom.holds else "[yellow]does not hold[/]"
            console.print(f"      {atom}  {mark}")
