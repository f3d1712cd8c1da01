"""The periodic loop that executes a mission (DESIGN "Semantics of one cycle"):

1. read the driver, update the kinematics;
2. check the active states' clauses, innermost first, and fire those that hold (see
   :mod:`robocop_dsl.runtime.statechart`);
3. run the active states' ``during`` actions, outermost first;
4. compute the QP command and write it to the driver; observers get a copy.

``controller.failed`` is true in the cycle after a cycle whose QP had no solution or
whose driver stopped answering. A fault that no clause handles ends the run with
outcome ``fault``; whatever ends a run, the robot is left holding (zero velocity) and
every observer's ``on_stop`` runs.
"""

from __future__ import annotations

import time as clock

import numpy as np

from ..diagnostics import RobocopError
from .program import Program
from .records import CycleRecord, Event
from .result import RunResult, TransitionRecord
from .statechart import Statechart
from .views import TaskViews, task_views


class Runner:
    """Runs a :class:`Program` with a controller, its kinematics and a driver.

    Args:
        program: The executable mission.
        controller: A :class:`robocop_dsl.control.Controller`.
        driver: An object with ``read() -> (q, v)``, ``write(velocity)`` and ``hold()``.
        name: The mission's name, for reports.

    Attributes:
        chart: The :class:`~robocop_dsl.runtime.statechart.Statechart` running the
            program's machines.
    """

    def __init__(self, program: Program, controller, driver, name: str = "mission"):
        self.program = program
        self.controller = controller
        self.kinematics = controller.kinematics
        self.driver = driver
        self.name = name
        self.time_step = controller.time_step
        self.joint_names = list(controller.joint_group.joints)
        self.observers: list = []
        self._wants_tasks = False
        self.cycle = 0
        self.failed = False
        self.chart = Statechart(program, self._on_transition)
        self._in_cycle = False
        self._steps: tuple = ()
        self._started = False
        self._done: str | None = None
        self._message = ""
        self._driver_lost = False
        self._held = False
        self._attached: dict = {}
        self._transitions: list = []
        self._cycle_times: list = []
        self._compute_times: list = []
        self._qp_failures = 0
        self._overruns = 0
        self.q = None

    def __repr__(self) -> str:
        return f"Runner({self.name}, state={self.state}, t={self.time:.3f}s)"

    @property
    def state(self) -> str:
        """The active configuration: the active leaf states' paths in declaration order,
        joined by `` | `` (``pick/above``, ``both/left/above | both/right/down``)."""
        return self.chart.configuration

    @property
    def time(self) -> float:
        """Mission time [s] (rounded to the nanosecond)."""
        return round(self.cycle * self.time_step, 9)

    @property
    def finished(self) -> bool:
        return self._done is not None

    def add_observer(self, observer) -> None:
        self.observers.append(observer)
        self._wants_tasks = any(o.wants_tasks for o in self.observers)

    def task_views(self) -> TaskViews:
        """The enabled tasks at the latest cycle (targets and references in the world)."""
        return task_views(self.controller)

    def emit(self, event: str) -> None:
        """Raise ``event``: ``event NAME`` conditions see it from the next cycle on while
        their owner state stays. Raised between cycles, it counts as raised in the last
        completed cycle."""
        cycle = self.cycle if self._in_cycle else max(self.cycle - 1, 0)
        self.chart.raise_event(event, cycle)
        self._notify_event("event", {"name": event})

    def log(self, text: str) -> None:
        """A ``log`` event; its ``state`` is the path of the state whose block or clause
        logs, else the configuration."""
        self._notify_event("log", {"message": text, "state": self.chart.running or self.state})

    def attach(self, body: str, parent: str) -> None:
        """Make ``body`` move rigidly with ``parent`` from now on."""
        self.kinematics.attach(body, parent)
        self._attached[body] = self.kinematics.frame_id(body)
        self._notify_event("action", {"action": "attach", "body": body, "to": parent})

    def detach(self, body: str) -> None:
        """Leave ``body`` fixed in the world where it is."""
        self.kinematics.detach(body)
        self._attached.pop(body, None)
        self._notify_event("action", {"action": "detach", "body": body})

    def _notify_event(self, kind: str, data: dict) -> None:
        event = Event(kind, self.time, self.cycle, data)
        for observer in self.observers:
            observer.on_event(event)

    def _start(self) -> None:
        self._started = True
        for observer in self.observers:
            observer.on_start(self)
        self._notify_event("start", {"state": self.state})
        try:
            self.driver.connect()
            self.q, _ = self.driver.read()
        except RobocopError as error:
            self._driver_fault(error)
            self._finish("fault", f"driver: {error}")
            return
        self.kinematics.update(self.q)
        self._macro(self.chart.start(self))

    def _macro(self, step) -> None:
        """Keep the micro steps of ``step`` for this cycle's record; end the run when it
        entered a final state of the mission's machine."""
        self._steps = self._steps + step.steps
        if step.outcome is not None:
            self._finish(step.outcome, f"reached final state '{step.final}'")

    def _finish(self, outcome: str, message: str) -> None:
        if self._done is None:
            self._done = outcome
            self._message = message

    def _read(self) -> None:
        if self._driver_lost:
            return
        try:
            self.q, _ = self.driver.read()
        except RobocopError as error:
            self._driver_fault(error)

    def _driver_fault(self, error: Exception) -> None:
        self._driver_lost = True
        self.failed = True
        self._notify_event("fault", {"message": f"driver: {error}", "state": self.state})

    def _on_transition(self, source: str, target: str, condition: str) -> None:
        """A clause fires (before its actions): record it and tell the observers."""
        self._transitions.append(TransitionRecord(self.time, source, target, condition))
        self._notify_event("transition", {"from": source, "to": target,
                                          "condition": condition})

    def _unhandled_failure(self) -> bool:
        return self.failed and not self.chart.handles_failure()

    def step(self) -> bool:
        """Run one cycle; return ``False`` once the mission has ended."""
        self._in_cycle = True
        try:
            return self._cycle()
        finally:
            self._in_cycle = False

    def _cycle(self) -> bool:
        if not self._started:
            self._start()
        if self._done is not None:
            return False
        started = clock.perf_counter()
        self._read()
        before_kinematics = clock.perf_counter()
        self.kinematics.update(self.q)
        kinematics_time = clock.perf_counter() - before_kinematics
        if self._unhandled_failure():
            self._finish("fault", self._message or "run-time fault with no handler")
        else:
            self._macro(self.chart.transitions(self))
        if self._done is None:
            self.chart.during(self)
        command, solved, compute_time = self._command()
        self._write(command)
        self._record(command, solved, kinematics_time + compute_time,
                     clock.perf_counter() - started)
        self._cycle_times.append(clock.perf_counter() - started)
        self.cycle += 1
        return self._done is None

    def _command(self):
        if self._done is not None or self._driver_lost:
            return np.zeros(len(self.joint_names)), True, 0.0
        result = self.controller.compute(self.q)
        self.failed = not result.solved
        if not result.solved:
            self._qp_failures += 1
            self._message = f"no QP solution in state '{self.state}': {result.reason}"
            self._notify_event("qp_failure", {"message": result.reason, "state": self.state,
                                              "repeat": self._qp_failures > 1})
        return result.velocity, result.solved, result.timings.total

    def _write(self, command: np.ndarray) -> None:
        if self._driver_lost:
            return
        try:
            if self._done is None:
                self.driver.write(command)
            else:
                self.driver.hold()
                self._held = True
        except RobocopError as error:
            self._driver_fault(error)

    def _record(self, command, solved, compute_time, cycle_time) -> None:
        """Hand observers a copy of the cycle; ``compute_time`` [s] is the controller's
        work (kinematics and QP), ``cycle_time`` [s] the cycle before observers."""
        self._compute_times.append(compute_time)
        steps, self._steps = self._steps, ()
        if not self.observers:
            return
        bodies = {b: self.kinematics.pose(f).homogeneous.copy()
                  for b, f in self._attached.items()}
        record = CycleRecord(self.cycle, self.time, self.state, self.q.copy(),
                             self.q[self.controller.joint_group.q_indices],
                             np.array(command, dtype=float), solved,
                             self.task_views() if self._wants_tasks else (), bodies,
                             compute_time, cycle_time, steps)
        for observer in self.observers:
            observer.on_cycle(record)

    def run(self, duration: float | None = None, realtime: bool = False) -> RunResult:
        """Run until a final state, a fault, ``duration`` [s] of mission time or Ctrl-C."""
        wall_start = clock.perf_counter()
        try:
            while self.step():
                if duration is not None and self.time >= duration - 1e-12:
                    self._finish("stopped", f"duration of {duration:g} s reached")
                    self._hold()
                    break
                if realtime:
                    self._sleep_to(wall_start + self.cycle * self.time_step)
        except KeyboardInterrupt:
            self._finish("interrupted", "interrupted (Ctrl-C)")
            self._hold()
        return self._close()

    def _sleep_to(self, deadline: float) -> None:
        remaining = deadline - clock.perf_counter()
        if remaining > 0:
            clock.sleep(remaining)
        elif -remaining > self.time_step:
            self._overruns += 1
            self._notify_event("overrun", {"message": f"cycle late by {-remaining * 1e3:.2f} ms",
                                           "late": -remaining})

    def _holding(self) -> bool:
        """Whether the last command the robot got is a hold (or no robot answers)."""
        return self._driver_lost or self._held

    def _hold(self) -> None:
        if not self._driver_lost:
            try:
                self.driver.hold()
                self._held = True
            except RobocopError as error:
                self._driver_fault(error)

    def _close(self) -> RunResult:
        result = RunResult(self._done or "stopped", self.state, self.time, self.cycle,
                           list(self._transitions), np.array(self._cycle_times),
                           np.array(self._compute_times), self._qp_failures, self._overruns,
                           self._message)
        self._notify_event("end", {"outcome": result.outcome, "state": result.final_state,
                                   "message": result.message,
                                   "holding": self._holding()})
        for observer in self.observers:
            observer.on_stop(result)
        self.driver.disconnect()
        return result
