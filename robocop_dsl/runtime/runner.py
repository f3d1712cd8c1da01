"""The periodic loop that executes a mission (DESIGN "Semantics of one cycle"):

1. read the driver (its state checked, :mod:`robocop_dsl.safety.robot_state`), update
   the kinematics;
2. check the active states' clauses, innermost first, and fire those that hold (see
   :mod:`robocop_dsl.runtime.statechart`);
3. run the active states' ``during`` actions, outermost first;
4. compute the QP command and write it to the driver; observers get a copy.

``controller.failed`` is true in the cycle after a cycle whose QP was relaxed, spent
its solver's budget or had no solution, or whose driver stopped answering. A fault that
no clause handles, and any exception in the loop (a clause, an action, a task, an
observer, the driver), ends the run with outcome ``fault``.

Stopping: whatever ends a run (a final state, the duration, a fault, :meth:`Runner.stop`)
the robot is brought to rest by the braking QP (:mod:`robocop_dsl.safety.braking`):
every cycle the velocity goes towards zero as fast as the acceleration limits allow,
every enabled constraint held, then the robot holds (zero velocity). Those cycles are
run and recorded like any other, in the state that ended the run; every observer's
``on_stop`` runs after them.
"""

from __future__ import annotations

import time as clock
import traceback

import numpy as np

from ..diagnostics import RobocopError
from ..safety import RobotStateCheck, RunGuard
from .cycle_times import CycleTimes
from .faults import error_text, fault_place, origin
from .program import Program
from .records import CycleRecord, Event
from .result import RunResult, TransitionRecord
from .sensors import Sensors
from .statechart import Statechart
from .variables import Variables
from .views import TaskViews, task_views

_FAILED = {"solver_budget": "the QP solver found no answer within its iteration budget",
           "relaxed": "its constraints had no common command and were relaxed"}
"""What a cycle that is not solved says of itself, by status (``no_solution`` says it
in the ``qp_failure`` message)."""


class Runner:
    """Runs a :class:`Program` with a controller, its kinematics and a driver.

    Use :meth:`run`, or drive the loop yourself: :meth:`start` (optional: the first
    :meth:`step` starts), :meth:`step` once per control period until it returns
    ``False``, then :meth:`finish` for the :class:`RunResult`. :meth:`emit` raises an
    event and :meth:`stop` ends the run from anywhere (another thread, a signal
    handler).

    Args:
        program: The executable mission.
        controller: A :class:`robocop_dsl.control.Controller`.
        driver: An object with ``read() -> (q, v)``, ``write(velocity)`` and ``hold()``.
        name: The mission's name, for reports.

    Attributes:
        chart: The :class:`~robocop_dsl.runtime.statechart.Statechart` running the
            program's machines.
        error: The exception that ended the run with a fault, or ``None`` (its
            traceback is :meth:`fault_traceback`).
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
        self.error: BaseException | None = None
        self._raised: BaseException | None = None
        self.chart = Statechart(program, self._on_transition)
        self._in_cycle = False
        self._steps: tuple = ()
        self._started = False
        self._done: str | None = None
        self._message = ""
        self._stop_request: tuple | None = None
        self._driver_lost = False
        self._held = False
        self.guard = RunGuard(controller, self._notify_event)
        """The safety layer's part of the run (:mod:`robocop_dsl.safety.guard`)."""
        self._last_command = np.zeros(len(self.joint_names))
        self._result: RunResult | None = None
        self._clock_start: float | None = None
        self._broken: set = set()
        self._attached: dict = {}
        self.free_bodies = {body: self.kinematics.frame_id(body)
                            for body in controller.world.free_bodies()}
        """The world's free bodies (frame ids): their poses are in every cycle's record."""
        self.variables = Variables(program.variables)
        """The mission's vars and their values (:mod:`robocop_dsl.runtime.variables`)."""
        self._transitions: list = []
        self._times = CycleTimes()
        self._qp_failures = 0
        self._overruns = 0
        self.q = None
        self._robot_state = RobotStateCheck.for_controller(controller)
        self.sensors = Sensors(controller.world)
        """The world's force sensors, read after the driver every cycle
        (:mod:`robocop_dsl.runtime.sensors`); force tasks read them."""
        controller.sensors = self.sensors

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
        """Whether the run has ended: its outcome is decided and the robot holds."""
        return self._done is not None and self._holding()

    @property
    def outcome(self) -> str | None:
        """The run's outcome once decided (the robot may still be stopping), else
        ``None``."""
        return self._done

    def add_observer(self, observer) -> None:
        self.observers.append(observer)
        self._wants_tasks = any(o.wants_tasks for o in self.observers)

    def task_views(self) -> TaskViews:
        """The enabled tasks at the latest cycle (targets and references in the world)."""
        return task_views(self.controller)

    def tasks(self) -> tuple:
        """Every task of the mission (enabled or not), of every controller."""
        return self.controller.tasks()

    # ---- the public loop ------------------------------------------------------------

    def start(self) -> None:
        """Begin the run: observers' ``on_start``, the ``start`` event, the driver
        connected and read, the start state entered. The first :meth:`step` calls it
        when not called before; calling it again does nothing."""
        if self._started:
            return
        self._started = True
        for observer in list(self.observers):
            self._call(observer, "on_start", self)
        self._notify_event("start", {"state": self.state,
                                     "world": str(self.controller.world.path)})
        try:
            self.driver.connect()
            q, v = self.driver.read()
            self._robot_state.require(q, v)
            self.q = q
        except Exception as error:  # any driver failure is the run's fault
            self._driver_fault(error)
            self._finish("fault", f"driver: {error_text(error)}")
            return
        try:
            self.kinematics.update(self.q)
            self.variables.start(self)
            self._macro(self.chart.start(self))
            self.controller.prepare(self.q)
        except Exception as error:  # an enter block of the start states, a constraint raised
            self._fault(error)

    def step(self) -> bool:
        """Run one control cycle; ``False`` once the run has ended (outcome decided,
        the robot brought to rest and holding): then call :meth:`finish`."""
        self._in_cycle = True
        try:
            return self._cycle()
        finally:
            self._in_cycle = False

    def stop(self, message: str = "stopped by the caller", outcome: str = "interrupted") -> None:
        """End the run at the start of the next cycle with ``outcome`` and ``message``
        (unless it already ended); the robot then decelerates and holds over the next
        :meth:`step` calls. Safe from a signal handler or another thread."""
        self._stop_request = (outcome, message)

    def finish(self) -> RunResult:
        """End the run and return its result; the same result when called again.

        A run still going is stopped first (outcome ``interrupted``) and its robot
        decelerated at the control period (keeping to the wall clock when the driver
        does). Then the ``end`` event, every observer's ``on_stop`` and the driver's
        ``disconnect``.
        """
        if self._result is not None:
            return self._result
        if not self.finished:
            if self._done is None:
                self.stop("finished before the mission ended")
            deadline = clock.perf_counter()
            while self.step():
                if self.driver_realtime:
                    deadline += self.time_step
                    clock.sleep(max(deadline - clock.perf_counter(), 0.0))
        return self._close()

    def run(self, duration: float | None = None, realtime: bool = False) -> RunResult:
        """Run until a final state, a fault, ``duration`` [s] of mission time,
        :meth:`stop` or Ctrl-C (a second Ctrl-C while the robot stops holds it at once);
        return :meth:`finish`'s result. Real time counts from the end of :meth:`start`
        (the observers' set-up takes what it takes)."""
        wall_start = clock.perf_counter()
        try:
            self.start()
            wall_start = clock.perf_counter()
            self._clock_start = wall_start if realtime else None
            self._loop(duration, realtime, wall_start)
        except KeyboardInterrupt:
            self.stop("interrupted (Ctrl-C)")
            try:
                self._loop(None, realtime, wall_start)
            except KeyboardInterrupt:
                self._finish("interrupted", "interrupted (Ctrl-C)")
                self._hold()
        return self.finish()

    @property
    def next_cycle_at(self) -> float | None:
        """When the next cycle starts [s, ``time.perf_counter()``] in a real-time
        :meth:`run`; ``None`` in a headless one."""
        if self._clock_start is None:
            return None
        return self._clock_start + (self.cycle + 1) * self.time_step

    @property
    def driver_realtime(self) -> bool:
        """Whether the driver's robot follows the wall clock."""
        return bool(getattr(self.driver, "realtime", False))

    def fault_traceback(self) -> str:
        """The traceback of the exception that ended the run (empty if none)."""
        if self._raised is None:
            return ""
        return "".join(traceback.format_exception(self._raised))

    def emit(self, event: str) -> None:
        """Raise ``event``: ``event NAME`` conditions see it from the next cycle on while
        their owner state stays. Raised between cycles, it counts as raised in the last
        completed cycle."""
        cycle = self.cycle if self._in_cycle else max(self.cycle - 1, 0)
        self.chart.raise_event(event, cycle)
        self._notify_event("event", {"name": event})

    def report(self, kind: str, data: dict) -> None:
        """An event about the run from one of its observers (``dropped``: a writer fell
        behind and dropped data), heard by every observer."""
        self._notify_event(kind, data)

    def log(self, text: str) -> None:
        """A ``log`` event; its ``state`` is the path of the state whose block or clause
        logs, else the configuration."""
        self._notify_event("log", {"message": text, "state": self.chart.running or self.state})

    def assign(self, name: str, value) -> None:
        """Give var ``name`` (its qualified name) the value ``value`` [SI]; an
        ``assign`` event says so."""
        stored = self.variables.set(name, value)
        self._notify_event("assign", {"var": name, "value": stored,
                                      "state": self.chart.running or self.state})

    def set_pose(self, body: str, pose) -> None:
        """Move ``body`` to ``pose`` (``pin.SE3`` or 4x4, world frame) before the next
        cycle, as a perception pipeline reports where an object is: a body fixed to the
        world is placed there; a free body is put there by its driver (physics)."""
        import pinocchio as pin

        pose = pose if isinstance(pose, pin.SE3) else pin.SE3(np.asarray(pose, dtype=float))
        if body in self.free_bodies:
            if not hasattr(self.driver, "set_pose"):
                raise ValueError(f"'{body}' is a free body: its driver places it, and "
                                 f"{type(self.driver).__name__} cannot")
            self.driver.set_pose(body, pose)
        else:
            if not self.kinematics.is_fixed(self.kinematics.frame_id(body)):
                raise ValueError(f"'{body}' is carried by a joint: only a body fixed to the "
                                 "world or a free body can be moved")
            self.kinematics.place(body, "world", pose)
            self._attached[body] = self.kinematics.frame_id(body)
        self._notify_event("action", {"action": "set_pose", "body": body,
                                      "position": pose.translation.tolist(),
                                      "orientation": pin.Quaternion(pose.rotation).coeffs()
                                      .tolist()})

    def attach(self, body: str, parent: str) -> None:
        """Make ``body`` move rigidly with ``parent`` from now on: in physics, a weld
        between them (``body`` must be free); else its frame moves to ``parent``."""
        if hasattr(self.driver, "attach"):
            self.driver.attach(body, parent)
        else:
            self.kinematics.attach(body, parent)
            self._attached[body] = self.kinematics.frame_id(body)
        self._notify_event("action", {"action": "attach", "body": body, "to": parent})

    def detach(self, body: str) -> None:
        """Release ``body``: in physics its weld is released and it falls unless
        something holds it; else it stays fixed in the world where it is."""
        if hasattr(self.driver, "detach"):
            self.driver.detach(body)
        else:
            self.kinematics.detach(body)
            self._attached.pop(body, None)
        self._notify_event("action", {"action": "detach", "body": body})

    # ---- one cycle ------------------------------------------------------------------

    def _loop(self, duration: float | None, realtime: bool, wall_start: float) -> None:
        while self.step():
            if (duration is not None and self._done is None
                    and self.time >= duration - 1e-12):
                self._finish("stopped", f"duration of {duration:g} s reached")
            if realtime:
                self._sleep_to(wall_start + self.cycle * self.time_step)

    def _cycle(self) -> bool:
        if not self._started:
            self.start()
        if self.finished:
            return False
        if self._done is None and self._stop_request is not None:
            self._finish(*self._stop_request)
        started = clock.perf_counter()
        self._read()
        compute_time = 0.0
        command, solved = None, True
        try:
            before_kinematics = clock.perf_counter()
            self.kinematics.update(self.q)
            compute_time = clock.perf_counter() - before_kinematics
            if self._done is None:
                if self._unhandled_failure():
                    self._finish("fault", self._message or "run-time fault with no handler")
                else:
                    self._macro(self.chart.transitions(self))
            if self._done is None:
                self.chart.during(self)
            if self._done is None:
                command, solved, qp_time = self._command()
                compute_time += qp_time
        except Exception as error:  # whatever raises in the loop ends the run safely
            self._fault(error)
        if command is None:
            command = self._stopping_command()
        self.guard.observe(command, self._last_command)
        self._write(command)
        self._record(command, solved, compute_time, clock.perf_counter() - started)
        self._times.add(clock.perf_counter() - started, compute_time)
        self.cycle += 1
        return not self.finished

    def _command(self):
        if self._driver_lost:
            return np.zeros(len(self.joint_names)), True, 0.0
        result = self.controller.compute(self.q)
        self.failed = not result.solved
        self.guard.announce(result, self.state)
        if not result.solved and result.status in _FAILED:
            self._message = f"the controller failed in state '{self.state}': " \
                            f"{_FAILED[result.status]}"
        if result.status == "no_solution":
            self._qp_failures += 1
            self._message = f"no QP solution in state '{self.state}': {result.reason}"
            self._notify_event("qp_failure", {"message": result.reason, "state": self.state,
                                              "repeat": self._qp_failures > 1})
            result = self.controller.brake(self.q, previous=self._last_command)
        return result.velocity, result.solved, result.timings.total

    def _stopping_command(self) -> np.ndarray:
        """The command of a cycle after the outcome was decided: the braking QP's
        (:meth:`~robocop_dsl.safety.guard.RunGuard.brake`); zero if a constraint raises."""
        try:
            return self.guard.brake(self.q, self._last_command, self.state, self._driver_lost)
        except Exception as error:  # a constraint that raises: hold rather than move
            self._fault(error)
            return np.zeros(len(self.joint_names))

    def _write(self, command: np.ndarray) -> None:
        if self._driver_lost:
            return
        at_rest = self._done is not None and not np.any(command)
        try:
            if at_rest:
                self.driver.hold()
            else:
                self.driver.write(command)
        except Exception as error:  # any driver failure is the run's fault
            self._driver_fault(error)
            return
        self._last_command = np.array(command, dtype=float)
        self._held = at_rest

    def _read(self) -> None:
        if self._driver_lost:
            return
        try:
            q, v = self.driver.read()
            self._robot_state.require(q, v)
            self.q = q
            self.sensors.update(self.driver, self.time_step)
        except Exception as error:  # any driver failure is the run's fault
            self._driver_fault(error)

    def wrench(self, body: str) -> np.ndarray:
        """The latest reading of the force sensor on ``body``: ``[fx, fy, fz, tx, ty,
        tz]`` [N, N m], what the body exerts on the environment, world frame (see
        :mod:`robocop_dsl.runtime.sensors`)."""
        return self.sensors.wrench(body)

    def contact(self, first: str, second: str) -> bool:
        """Whether the driver's physics has a contact between sets ``first`` and
        ``second`` (each a body, or a joint group or joint) now."""
        return self.sensors.contact(first, second)

    def _record(self, command, solved, compute_time, cycle_time) -> None:
        """Hand observers a copy of the cycle; ``compute_time`` [s] is the controller's
        work (kinematics and QP), ``cycle_time`` [s] the cycle before observers."""
        steps, self._steps = self._steps, ()
        if not self.observers:
            return
        bodies = {b: self.kinematics.pose(f).homogeneous
                  for moved in (self.free_bodies, self._attached) for b, f in moved.items()}
        record = CycleRecord(self.cycle, self.time, self.state, self.q.copy(),
                             self.controller.joint_group.positions(self.q),
                             np.array(command, dtype=float), solved,
                             self.task_views() if self._wants_tasks else (), bodies,
                             compute_time, cycle_time, steps,
                             wrenches=self.sensors.readings(),
                             variables=dict(self.variables.values))
        for observer in list(self.observers):
            self._call(observer, "on_cycle", record)

    # ---- ending ---------------------------------------------------------------------

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

    def _fault(self, error: BaseException, where: str | None = None) -> None:
        """End the run with outcome ``fault`` for ``error`` raised in the loop."""
        message = f"{where or fault_place(error, self.state)}: {error_text(origin(error))}"
        self.failed = True
        if self._done is None:
            self.error, self._raised = origin(error), error
            self._finish("fault", message)
        self._notify_event("fault", {"message": message, "state": self.state})

    def _driver_fault(self, error: Exception) -> None:
        self._driver_lost = True
        self.failed = True
        if self._done is None:
            self._message = f"driver: {error_text(error)}"
            if not isinstance(error, RobocopError):
                self.error = self._raised = error
        self._notify_event("fault", {"message": f"driver: {error_text(error)}",
                                     "state": self.state})

    def _on_transition(self, source: str, target: str, condition: str) -> None:
        """A clause fires (before its actions): record it and tell the observers."""
        self._transitions.append(TransitionRecord(self.time, source, target, condition))
        self._notify_event("transition", {"from": source, "to": target,
                                          "condition": condition})

    def _unhandled_failure(self) -> bool:
        return self.failed and not self.chart.handles_failure()

    def _notify_event(self, kind: str, data: dict) -> None:
        event = Event(kind, self.time, self.cycle, data)
        for observer in list(self.observers):
            self._call(observer, "on_event", event)

    def _call(self, observer, hook: str, argument) -> None:
        """``observer.hook(argument)``; an observer that raises is a fault and hears
        nothing more but ``on_stop``."""
        if id(observer) in self._broken:
            return
        try:
            getattr(observer, hook)(argument)
        except Exception as error:  # an observer's bug must not leave the robot moving
            self._broken.add(id(observer))
            self._fault(error, f"observer {type(observer).__name__}.{hook} in state "
                               f"'{self.state}'")

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
            except Exception as error:  # any driver failure is the run's fault
                self._driver_fault(error)

    def _close(self) -> RunResult:
        cycle_times, compute_times = self._times.arrays()
        message = self._message
        if self.guard.stopping_cycles > 1:
            stop = self.guard.stopping_cycles * self.time_step
            message += f"; brought to rest in {stop:.3f} s by the braking QP"
        result = RunResult(self._done or "stopped", self.state, self.time, self.cycle,
                           list(self._transitions), cycle_times, compute_times,
                           self._qp_failures, self._overruns, message, self.guard.report)
        self._notify_event("end", {"outcome": result.outcome, "state": result.final_state,
                                   "message": result.message,
                                   "holding": self._holding(),
                                   "safety": self.guard.report.as_event()})
        for observer in self.observers:
            try:
                observer.on_stop(result)
            except Exception as error:  # every observer gets its on_stop
                result.message += (f"; observer {type(observer).__name__}.on_stop: "
                                   f"{error_text(error)}")
        try:
            self.driver.disconnect()
        except Exception as error:  # the run is over: report, do not raise
            result.message += f"; driver disconnect: {error_text(error)}"
        self._result = result
        return result
