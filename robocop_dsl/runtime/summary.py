"""Why a run ended the way it did: the enabled tasks' final errors, and for a run that did
not succeed, the clause that fired and how far every other clause of its state was from
holding (``left_tool.error < 1 mm: 4.2 mm``).

A :class:`SummaryWatch` observes a run. When a clause fires it reads, through the
runner's public state (its controller's tasks, kinematics, statechart and time), the
conditions of the compiled mission (:mod:`robocop_dsl.compile.spec`) of every other
clause that was checked with it, at that very cycle; at the end it builds a
:class:`RunSummary`.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

from ..compile import spec as s
from ..compile import variables as v
from ..control.exceptions import UnknownName
from .cascade import PENDING
from .cascade import TaskStatus as RemoteStatus
from .clearance import Clearance
from .records import Observer
from .variables import evaluator

KEPT_FIRINGS = 64   # the latest firings kept: enough for any chain of nested outcomes
TASK_UNITS = {"joint_position": "rad", "joint_velocity": "rad/s", "body_position": "m",
              "body_orientation": "rad", "body_pose": "m", "body_velocity": "m/s",
              "gaze": "rad", "body_force": "N"}


def format_quantity(value: float, unit: str) -> str:
    """``value`` [SI ``unit``] for a reader: lengths below 1 m in mm, angles in deg."""
    if value is None or not math.isfinite(value):
        return "n/a"
    if unit == "m" and abs(value) < 1.0:
        return f"{value * 1e3:.3g} mm"
    if unit == "rad":
        return f"{math.degrees(value):.3g} deg"
    if unit == "rad/s":
        return f"{math.degrees(value):.3g} deg/s"
    if unit == "":
        return f"{value:g}"
    return f"{value:.4g} {unit}"


@dataclass(frozen=True)
class TaskStatus:
    """A task enabled at the end: ``errors`` is a tuple of ``(label, value [SI], unit)``
    (``position`` and ``orientation`` for a pose task, else one ``error``)."""

    name: str
    kind: str
    target: str
    errors: tuple
    reached: bool

    def error_text(self) -> str:
        if len(self.errors) == 1:
            return format_quantity(self.errors[0][1], self.errors[0][2])
        return ", ".join(f"{label} {format_quantity(value, unit)}"
                         for label, value, unit in self.errors)


@dataclass(frozen=True)
class AtomStatus:
    """One elementary condition of a clause: its ``text``, whether it ``holds`` and
    what it measured (``4.2 mm``, ``no``, ``not raised``)."""

    text: str
    holds: bool
    value: str

    def __str__(self) -> str:
        return f"{self.text}: {self.value}"


@dataclass(frozen=True)
class ClauseStatus:
    """A clause checked with the one that fired: the ``state`` that owns it, its
    condition ``text``, its ``target`` and the status of each elementary condition."""

    state: str
    text: str
    target: str
    atoms: tuple


@dataclass(frozen=True)
class Firing:
    """A clause that fired at ``time`` [s] from ``source`` to ``target``, with every
    other clause checked in that state at that cycle (``others``)."""

    time: float
    source: str
    target: str
    condition: str
    others: tuple


@dataclass(frozen=True)
class RunSummary:
    """``tasks``: the tasks enabled when the run ended (when a clause ended it: just
    before that clause's exits); ``fired``: the clauses that led to the end, innermost
    first, when the run did not succeed; ``pending``: when no clause ended the run
    (duration, fault, interruption), the clauses of the active states at the end."""

    outcome: str
    tasks: tuple
    fired: tuple = ()
    pending: tuple = ()


class SummaryWatch(Observer):
    """Observes a run to explain its end; :attr:`summary` is set when it stops.

    Args:
        mission: The compiled mission (:class:`~robocop_dsl.compile.spec.MissionSpec`).
    """

    wants_tasks = False

    def __init__(self, mission: s.MissionSpec):
        self.mission = mission
        self.states = mission.states
        self.machines = {}
        self.parents = {}
        self._index(mission.machine, None)
        self.finals = {path for path, state in self.states.items()
                       if state.final and self.machine_of(path) == ""}
        self.runner = None
        self.summary: RunSummary | None = None
        self._firings: deque = deque(maxlen=KEPT_FIRINGS)
        self._final_tasks: tuple | None = None

    def _index(self, machine: s.MachineSpec, parent: str | None) -> None:
        self.machines[machine.path] = machine
        self.parents[machine.path] = parent
        for state in machine.states.values():
            for nested in state.machines:
                self._index(nested, state.path)

    def machine_of(self, path: str) -> str:
        """The path of the machine the state at ``path`` belongs to."""
        for machine_path, machine in self.machines.items():
            if any(state.path == path for state in machine.states.values()):
                return machine_path
        raise KeyError(path)

    def on_start(self, runner) -> None:
        self.runner = runner

    def on_event(self, event) -> None:
        if event.kind != "transition" or self.runner is None:
            return
        source, target = event.data["from"], event.data["to"]
        if source not in self.states:
            return
        condition = event.data["condition"]
        self._firings.append(Firing(event.time, source, target, condition,
                                    tuple(self.clauses(source, skip=condition))))
        if target in self.finals:
            self._final_tasks = self.task_statuses()

    def on_stop(self, result) -> None:
        tasks = self._final_tasks if self._final_tasks is not None else self.task_statuses()
        fired, pending = (), ()
        if result.outcome == "failure":
            fired = tuple(self._chain())
        elif result.outcome != "success" and self.runner is not None:
            pending = tuple(clause for path in self._leaves() for clause in self.clauses(path))
        self.summary = RunSummary(result.outcome, tasks, fired, pending)

    def _leaves(self) -> list:
        chart = self.runner.chart
        active = set(chart.active())
        return [path for path in chart.active()
                if not any(other.startswith(path + "/") for other in active)]

    def _chain(self) -> list:
        """The last firing and, before it, those inside the state it left (a nested
        outcome that the parent's clause read), innermost first."""
        if not self._firings:
            return []
        chain = [self._firings[-1]]
        for firing in reversed(list(self._firings)[:-1]):
            if firing.target.startswith(chain[0].source + "/"):
                chain.insert(0, firing)
            else:
                break
        return chain

    def task_statuses(self) -> tuple:
        """The status of every task enabled now: the runner's controller's, then, in a
        cascade, the other controllers' (as of their last cycle)."""
        statuses = [self._status(t.name, t.kind, t) for t in self.runner.controller.tasks()
                    if t.enabled]
        remote = getattr(self.runner, "remote", None)
        if remote is not None:
            statuses += [self._status(name, self.mission.tasks[name].type, status)
                         for name, status in remote.enabled_tasks()]
        return tuple(statuses)

    def _status(self, name: str, kind: str, task) -> TaskStatus:
        """The status of the task ``name`` of type ``kind``, from ``task`` (a
        :class:`~robocop_dsl.control.Task` or another controller's :class:`RemoteStatus`)."""
        if kind == "body_pose":
            errors = (("position", task.position_error, "m"),
                      ("orientation", task.orientation_error, "rad"))
        else:
            errors = (("error", task.error, TASK_UNITS.get(kind, "")),)
        spec = self.mission.tasks.get(name)
        target = (spec.body or spec.joint_group or "") if spec is not None else ""
        return TaskStatus(name, kind, target, errors, bool(task.reached))

    def clauses(self, path: str, skip: str | None = None):
        """The clauses checked for the active state at ``path``, from it outwards: each
        state's own, then its machine's guards; ``skip`` is the text of one left out
        (the clause that fired)."""
        state = path
        while state is not None:
            machine = self.machine_of(state)
            owned = [(state, t) for t in self.states[state].transitions]
            owned += [(state, t) for t in self.machines[machine].guards]
            for owner, transition in owned:
                if transition.text == skip:
                    skip = None
                    continue
                yield ClauseStatus(owner, transition.text, transition.target,
                                   tuple(self.atoms(transition.condition, owner)))
            state = self.parents[machine]

    def atoms(self, condition, owner: str):
        """The elementary conditions of ``condition``, each with its status now, for a
        clause whose owner is the active state at ``owner``."""
        if isinstance(condition, s.NotCondition):
            for atom in self.atoms(condition.operand, owner):
                yield AtomStatus(f"not {atom.text}", not atom.holds, atom.value)
        elif isinstance(condition, (s.AllCondition, s.AnyCondition)):
            for operand in condition.operands:
                yield from self.atoms(operand, owner)
        else:
            yield self.atom(condition, owner)

    def atom(self, condition, owner: str) -> AtomStatus:
        runner = self.runner
        chart = runner.chart
        if isinstance(condition, s.CompareCondition):
            value, unit = self.measure(condition.measure, owner)
            bound = condition.value
            if isinstance(bound, v.VarValue):
                bound, shown = runner.variables.values[bound.name], bound.name
            else:
                shown = format_quantity(bound, unit)
            holds = _COMPARE[condition.operator](value, bound)
            text = f"{measure_text(condition.measure)} {condition.operator} {shown}"
            return AtomStatus(text, holds, format_quantity(value, unit))
        if isinstance(condition, v.ContactCondition):
            holds = runner.contact(condition.first, condition.second)
            return AtomStatus(f"contact({condition.first}, {condition.second})", holds,
                              "yes" if holds else "no")
        if isinstance(condition, s.ReachedCondition):
            task = self._task(condition.task)
            holds = task is not None and bool(task.reached)
            return AtomStatus(f"{condition.task}.reached", holds,
                              "yes" if holds else f"no ({self._error_text(task)})")
        if isinstance(condition, s.InterpolatedCondition):
            task = self._task(condition.task)
            holds = task is not None and self._finished(task)
            return AtomStatus(f"{condition.task}.interpolated", holds,
                              "yes" if holds else "no (interpolator running)")
        if isinstance(condition, s.ControllerFailedCondition):
            return AtomStatus("controller.failed", runner.failed,
                              "yes" if runner.failed else "no")
        if isinstance(condition, s.EventCondition):
            activation = chart.activation(owner)
            holds = activation is not None and chart.seen(condition.event, activation,
                                                          runner.cycle)
            return AtomStatus(f"event {condition.event}", holds,
                              "seen" if holds else "not raised")
        if isinstance(condition, s.FinalCondition):
            holds = chart.in_final(condition.state, condition.final, condition.region)
            parts = [condition.state, condition.region, condition.final]
            return AtomStatus(".".join(p for p in parts if p), holds,
                              "yes" if holds else f"no ({self._inside(condition.state)})")
        holds = chart.done(condition.state)
        return AtomStatus(f"{condition.state}.done", holds,
                          "yes" if holds else f"no ({self._inside(condition.state)})")

    def _inside(self, path: str) -> str:
        inside = [p for p in self.runner.chart.active() if p.startswith(path + "/")]
        leaves = [p for p in inside if not any(o.startswith(p + "/") for o in inside)]
        return "in " + " | ".join(leaves) if leaves else "not active"

    def _error_text(self, task) -> str:
        if task is None:
            return "not in this controller"
        if task is PENDING:
            return "its controller has not applied the last actions yet"
        if not task.enabled:
            return "disabled"
        state = "" if self._finished(task) else "interpolator running, "
        if isinstance(task, RemoteStatus):
            return f"{state}error {task.error:.3g}"
        return state + "error " + self._status(task.name, task.kind, task).error_text()

    def _task(self, name: str):
        """The task ``name`` of the runner's controller, or, run by another controller
        of a cascade, its latest status there (:class:`RemoteStatus`)."""
        remote = getattr(self.runner, "remote", None)
        if remote is not None and not remote.is_local(name):
            return remote.status(name)
        try:
            return self.runner.controller.task(name)
        except UnknownName:
            return None

    def _finished(self, task) -> bool:
        return task.interpolated if isinstance(task, RemoteStatus) else \
            task.interpolator().finished

    def measure(self, measure, owner: str) -> tuple:
        """The value [SI] of ``measure`` now and its unit."""
        runner = self.runner
        if isinstance(measure, s.ElapsedMeasure):
            activation = runner.chart.activation(owner)
            return (math.nan if activation is None else runner.time - activation.time), "s"
        if isinstance(measure, s.TimeMeasure):
            return runner.time, "s"
        if isinstance(measure, s.VisitsMeasure):
            return float(runner.chart.visits(measure.state)), ""
        if isinstance(measure, s.DistanceMeasure):
            return runner.kinematics.distance(measure.first, measure.second), "m"
        if isinstance(measure, s.ClearanceMeasure):
            return Clearance(measure.first, measure.second)(runner.kinematics), "m"
        if isinstance(measure, v.VarValue):
            return runner.variables.values[measure.name], runner.variables.specs[
                measure.name].unit
        if isinstance(measure, (v.PositionMeasure, v.WrenchMeasure)):
            unit = "m" if isinstance(measure, v.PositionMeasure) else \
                "Nm" if measure.torque else "N"
            return evaluator(measure)(runner, None), unit
        task = self._task(measure.task)
        if task is None:
            return math.nan, ""
        spec = self.mission.tasks.get(measure.task)
        unit = {"position_error": "m", "orientation_error": "rad"}.get(
            measure.field, TASK_UNITS.get(spec.type if spec else "", ""))
        return float(getattr(task, measure.field)), unit


def measure_text(measure) -> str:
    """A measure as written in a mission (``left_tool.error``, ``elapsed``)."""
    if isinstance(measure, s.ElapsedMeasure):
        return "elapsed"
    if isinstance(measure, s.TimeMeasure):
        return "time"
    if isinstance(measure, s.VisitsMeasure):
        return f"{measure.state}.visits"
    if isinstance(measure, s.DistanceMeasure):
        return f"distance({measure.first}, {measure.second})"
    if isinstance(measure, s.ClearanceMeasure):
        return f"clearance({measure.first}, {measure.second})"
    if isinstance(measure, v.VarValue):
        return measure.name
    if isinstance(measure, v.PositionMeasure):
        return f"{measure.body}.position" + ("" if measure.axis is None
                                             else "." + "xyz"[measure.axis])
    if isinstance(measure, v.WrenchMeasure):
        axis = "" if measure.axis is None else "." + "xyz"[measure.axis]
        return f"{'torque' if measure.torque else 'force'}({measure.body}){axis}"
    return f"{measure.task}.{measure.field}"


_COMPARE = {"<": lambda a, b: a < b, "<=": lambda a, b: a <= b,
            ">": lambda a, b: a > b, ">=": lambda a, b: a >= b}
