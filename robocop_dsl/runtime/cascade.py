"""Cascaded controllers: several controllers of one world, each on its own joint group,
world copy, driver and thread, at its own period (RoboCoP's cascaded worlds).

- The first controller (the fastest) runs the mission's state machine:
  :class:`CascadeRunner` is a :class:`Runner` that also exchanges data with the
  others. Each other controller runs in a :class:`ControllerThread`.
- A world is touched by its own thread only. At the start of its cycle a thread reads
  its driver, copies in the joint states the other threads published (one
  :class:`~robocop_dsl.drivers.AsyncWorldWriter` per reader) and publishes its own;
  the others' threads never see its world.
- Actions of the state machine on another controller's tasks and constraints (enable,
  targets, gains...) and bodies attached or detached travel through that controller's
  queue, drained at the start of its cycle. After its QP a thread publishes, under a
  lock, the :class:`TaskStatus` of its tasks and whether it failed; conditions read
  that, and ``controller.failed`` is true when any controller failed.
- In real time every thread keeps to ``start + k * time_step`` of one shared start.
  Otherwise a :class:`Lockstep` runs the cycles in the order of their mission time (the
  first controller first on a tie), so a run faster than real time is deterministic.
"""

from __future__ import annotations

import math
import queue
import threading
import time as clock
from dataclasses import dataclass, field

import numpy as np

from ..diagnostics import RobocopError
from ..drivers import AsyncWorldWriter
from ..safety import RobotStateCheck, stop_cycles
from .runner import Runner
from .views import TaskViews, task_views


@dataclass(frozen=True)
class TaskStatus:
    """A task of another controller as conditions see it, as of that controller's last
    cycle: ``reached``, ``interpolated``, and ``error``, ``position_error``,
    ``orientation_error`` in the task's units [m, rad...], and whether it is
    ``enabled``."""

    reached: bool
    interpolated: bool
    error: float
    position_error: float
    orientation_error: float
    enabled: bool = True


PENDING = TaskStatus(False, False, math.nan, math.nan, math.nan, False)
"""The status of a task whose controller has not yet applied every action sent to it:
not reached, and every comparison with its errors is false."""


@dataclass(frozen=True)
class ControllerStatus:
    """What a controller's thread publishes after each cycle.

    Attributes:
        cycle: Cycles run so far.
        applied: Actions of the state machine applied so far.
        failed: Whether the last cycle had no QP solution or the driver is lost.
        failures: Cycles without a QP solution so far.
        message: Why the last failure happened.
        fault: Why the thread stopped controlling (driver lost...), or ``None``.
        tasks: :class:`TaskStatus` by task name.
        views: The :class:`~robocop_dsl.runtime.views.TaskViews` of its enabled tasks,
            for observers.
    """

    cycle: int = 0
    applied: int = 0
    failed: bool = False
    failures: int = 0
    message: str = ""
    fault: str | None = None
    tasks: dict = field(default_factory=dict)
    views: TaskViews = TaskViews(())


class Link:
    """What the threads of a cascade exchange with one controller's thread.

    Args:
        name: The controller's name.
        group: The controller's joint group.
        readers: The names of the controllers that copy its joint state.
    """

    def __init__(self, name: str, group, readers):
        self.name = name
        self.group = group
        self.sent = 0
        self._states = {reader: AsyncWorldWriter(group) for reader in readers}
        self._actions: queue.SimpleQueue = queue.SimpleQueue()
        self._lock = threading.Lock()
        self._status = ControllerStatus()

    def __repr__(self) -> str:
        return f"Link({self.name}, {self.group.name})"

    def publish_state(self, q: np.ndarray, v: np.ndarray) -> None:
        """Publish the group's part of ``q`` (nq) and ``v`` (nv); owner thread only."""
        position, velocity = q[self.group.q_indices], v[self.group.v_indices]
        for writer in self._states.values():
            writer.sync(position, velocity)

    def copy_state(self, reader: str, q: np.ndarray, v: np.ndarray) -> None:
        """Write the latest published state into ``reader``'s ``q`` and ``v``, in place;
        ``reader``'s thread only."""
        self._states[reader].write(q, v)

    def send(self, action) -> None:
        """Queue ``action(thread)`` for the owner thread; state-machine thread only."""
        self.sent += 1
        self._actions.put(action)

    def take_actions(self) -> list:
        """Every queued action, in order; owner thread only."""
        actions = []
        while not self._actions.empty():
            actions.append(self._actions.get_nowait())
        return actions

    @property
    def status(self) -> ControllerStatus:
        """The latest status the owner thread published."""
        with self._lock:
            return self._status

    def publish_status(self, status: ControllerStatus) -> None:
        with self._lock:
            self._status = status


class Lockstep:
    """Runs the cycles of several threads one at a time, in the order of their mission
    time, then of their index.

    Args:
        count: The number of threads (indices ``0`` to ``count - 1``).
    """

    def __init__(self, count: int):
        self._next = [0.0] * count
        self._stopped = False
        self._turn = threading.Condition()

    def _first(self) -> int:
        return min(range(len(self._next)), key=lambda i: (self._next[i], i))

    def wait(self, index: int) -> bool:
        """Wait for thread ``index``'s turn; ``False`` once stopped."""
        with self._turn:
            self._turn.wait_for(lambda: self._stopped or self._first() == index)
            return not self._stopped

    def advance(self, index: int, time: float) -> None:
        """Thread ``index``'s next cycle is at mission ``time`` [s] (``inf``: none)."""
        with self._turn:
            self._next[index] = time
            self._turn.notify_all()

    def stop(self) -> None:
        """Release every waiting thread; no turn is given any more."""
        with self._turn:
            self._stopped = True
            self._turn.notify_all()


class Remote:
    """How the state machine reaches the tasks and constraints of the other controllers
    (the ``remote`` of :func:`robocop_dsl.runtime.build.build_program`).

    Args:
        owners: The controller running each task and constraint, by name.
        links: The :class:`Link` of every controller, by name.
        local: The controller that runs the state machine.
    """

    def __init__(self, owners: dict, links: dict, local: str):
        self._owners = owners
        self._links = links
        self.local = local

    def is_local(self, name: str) -> bool:
        return self._owners.get(name, self.local) == self.local

    def send(self, name: str, action) -> None:
        """Run ``action(thread)`` in the thread of the controller that runs ``name``."""
        self._links[self._owners[name]].send(action)

    def broadcast(self, action) -> None:
        """Run ``action(thread)`` in every other controller's thread."""
        for name, link in self._links.items():
            if name != self.local:
                link.send(action)

    def status(self, task: str) -> TaskStatus:
        """The task's latest status, :data:`PENDING` until its controller applied every
        action sent to it."""
        link = self._links[self._owners[task]]
        status = link.status
        if status.applied < link.sent:
            return PENDING
        return status.tasks.get(task, PENDING)

    def enabled_tasks(self) -> list:
        """``(name, status)`` of every task enabled in the other controllers, as of
        their last cycle (:data:`PENDING` for those of a controller that has not yet
        applied every action sent to it)."""
        return [(name, self.status(name)) for owner, link in self._links.items()
                if owner != self.local
                for name, status in link.status.tasks.items() if status.enabled]


class ControllerThread:
    """A controller of a cascade, other than the first, in a thread of its own.

    Args:
        name: The controller's name.
        controller: Its :class:`~robocop_dsl.control.Controller`, on its own world copy.
        driver: The driver of its joint group (connected in its thread).
        link: Its :class:`Link`.
        peers: The other controllers' links.
        index: Its index in the cascade (1 for the first after the state machine's).
    """

    def __init__(self, name: str, controller, driver, link: Link, peers, index: int):
        self.name = name
        self.controller = controller
        self.kinematics = controller.kinematics
        self.driver = driver
        self.link = link
        self.peers = list(peers)
        self.index = index
        self.cycle = 0
        self.overruns = 0
        self._applied = 0
        self._failures = 0
        self._fault: str | None = None
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._lockstep: Lockstep | None = None
        self._wall_start = 0.0
        self._robot_state = RobotStateCheck.for_controller(controller)

    def __repr__(self) -> str:
        return f"ControllerThread({self.name}, cycle={self.cycle})"

    @property
    def time(self) -> float:
        """Mission time of the next cycle [s]."""
        return round(self.cycle * self.controller.time_step, 9)

    def start(self, wall_start: float, lockstep: Lockstep | None) -> None:
        """Start the thread: in real time from ``wall_start`` (``perf_counter``) [s],
        else in ``lockstep``."""
        self._wall_start, self._lockstep = wall_start, lockstep
        self._thread = threading.Thread(target=self._run, name=f"controller {self.name}",
                                        daemon=True)
        self._thread.start()

    def stop(self) -> None:
        """Stop after the current cycle; the robot decelerates within its acceleration
        limits (see :mod:`robocop_dsl.runtime.runner`), then holds."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join()

    def _run(self) -> None:
        try:
            self.driver.connect()
            while self._fault is None and self._wait():
                self._cycle()
                if self._lockstep is not None:
                    self._lockstep.advance(self.index, self.time)
        except Exception as error:  # whatever stops the thread must reach the mission
            self._fail(f"{type(error).__name__}: {error}")
        finally:
            if self._lockstep is not None:
                self._lockstep.advance(self.index, math.inf)
            self._brake()
            self._release()

    def _brake(self) -> None:
        """Bring the robot to rest with the braking QP, one cycle per period (at the
        wall clock's pace in real time), unless the driver failed."""
        if self._fault is not None:
            return
        controller = self.controller
        deadline = clock.perf_counter()
        try:
            for _ in range(stop_cycles(controller.limits, controller.state.previous_command,
                                       controller.time_step)):
                if not np.any(controller.state.previous_command):
                    return
                if self._lockstep is None:
                    deadline += controller.time_step
                    clock.sleep(max(deadline - clock.perf_counter(), 0.0))
                q, v = self.driver.read()
                self._robot_state.require(q, v)
                self.driver.write(controller.brake(q).velocity)
        except Exception as error:  # the driver is lost: nothing more to command
            self._fail(f"driver: {error}")

    def _wait(self) -> bool:
        if self._lockstep is not None:
            return self._lockstep.wait(self.index) and not self._stop.is_set()
        remaining = self._wall_start + self.time - clock.perf_counter()
        if remaining > 0:
            self._stop.wait(remaining)
        if self._stop.is_set():
            return False
        if -remaining > self.controller.time_step:
            self.overruns += 1
        return True

    def _cycle(self) -> None:
        for action in self.link.take_actions():
            action(self)
            self._applied += 1
        try:
            q, v = self.driver.read()
            self._robot_state.require(q, v)
        except RobocopError as error:
            self._fail(f"driver: {error}")
            return
        for peer in self.peers:
            peer.copy_state(self.name, q, v)
        self.link.publish_state(q, v)
        sent = self.controller.state.previous_command
        result = self.controller.compute(q)
        command = result.velocity
        if result.status == "no_solution":      # brake from what was sent, not from zero
            command = self.controller.brake(q, previous=sent).velocity
        try:
            self.driver.write(command)
        except RobocopError as error:
            self._fail(f"driver: {error}")
            return
        self._failures += not result.solved
        self.cycle += 1
        self._publish(not result.solved, result.reason or "")

    def _publish(self, failed: bool, message: str) -> None:
        tasks = {t.name: TaskStatus(t.reached, t.interpolated, t.error, t.position_error,
                                    t.orientation_error, t.enabled)
                 for t in self.controller.tasks()}
        self.link.publish_status(ControllerStatus(self.cycle, self._applied, failed,
                                                  self._failures, message, self._fault,
                                                  tasks, task_views(self.controller)))

    def _fail(self, reason: str) -> None:
        self._fault = reason
        self._publish(True, reason)

    def _release(self) -> None:
        for release in (self.driver.hold, self.driver.disconnect):
            try:
                release()
            except RobocopError:
                pass


class CascadeRunner(Runner):
    """Runs a mission's state machine with the first controller of a cascade, the
    others in their :class:`ControllerThread`; :meth:`run` starts and stops them.

    Args:
        program: The program, built with ``remote``.
        controller: The first controller.
        driver: Its driver.
        name: The mission's name.
        link: The first controller's :class:`Link`.
        threads: The other controllers' threads.
        remote: The :class:`Remote` the program uses.
    """

    def __init__(self, program, controller, driver, name: str, link: Link, threads,
                 remote: Remote):
        super().__init__(program, controller, driver, name)
        self.link = link
        self.threads = list(threads)
        self.remote = remote
        self._v = np.zeros(self.kinematics.model.nv)
        self._reported = {t.name: (0, None) for t in self.threads}
        self._lockstep: Lockstep | None = None
        self._realtime: bool | None = None
        self._wall_start = clock.perf_counter()

    def run(self, duration: float | None = None, realtime: bool = False):
        """Start the other controllers, run the mission (see :meth:`Runner.run`), stop
        them; each brings its robot to rest and leaves it holding."""
        self._realtime = realtime
        return super().run(duration, realtime)

    def start(self) -> None:
        """Start the other controllers' threads (in lockstep unless the run keeps to
        the wall clock: :meth:`run`'s ``realtime``, else the driver's), then the
        mission (see :meth:`Runner.start`)."""
        if self._started:
            return
        realtime = self.driver_realtime if self._realtime is None else self._realtime
        self._lockstep = None if realtime else Lockstep(1 + len(self.threads))
        self._wall_start = clock.perf_counter()
        for thread in self.threads:
            thread.start(self._wall_start, self._lockstep)
        super().start()

    def tasks(self) -> tuple:
        """Every task of every controller of the cascade."""
        return super().tasks() + tuple(task for thread in self.threads
                                       for task in thread.controller.tasks())

    def step(self) -> bool:
        if not self._started:
            self.start()
        if self._lockstep is not None:
            self._lockstep.wait(0)
        alive = super().step()
        if alive and self._lockstep is not None:
            self._lockstep.advance(0, self.time)
        return alive

    def attach(self, body: str, parent: str) -> None:
        kinematics = self.kinematics
        placement = kinematics.pose(kinematics.frame_id(parent)).actInv(
            kinematics.pose(kinematics.frame_id(body)))
        super().attach(body, parent)
        self.remote.broadcast(lambda thread: thread.kinematics.place(body, parent, placement))

    def detach(self, body: str) -> None:
        pose = self.kinematics.body_pose(body)
        super().detach(body)
        self.remote.broadcast(lambda thread: thread.kinematics.place(body, "world", pose))

    def task_views(self) -> TaskViews:
        """The enabled tasks of every controller, the others' as of their last cycle."""
        views = super().task_views()
        for thread in self.threads:
            views = views + thread.link.status.views
        return views

    def _read(self) -> None:
        super()._read()
        for thread in self.threads:
            thread.link.copy_state(self.link.name, self.q, self._v)
        self._v[self.link.group.v_indices] = self.controller.state.previous_command
        self.link.publish_state(self.q, self._v)

    def _command(self):
        command = super()._command()
        for thread in self.threads:
            status = thread.link.status
            self.failed = self.failed or status.failed
            self._report(thread.name, status)
        return command

    def _report(self, name: str, status: ControllerStatus) -> None:
        """Tell the observers about another controller's new failures."""
        failures, fault = self._reported[name]
        if status.failures > failures:
            self._message = f"{name}: no QP solution in state '{self.state}': {status.message}"
            self._notify_event("qp_failure", {"message": f"{name}: {status.message}",
                                              "state": self.state, "repeat": failures > 0})
        if status.fault is not None and fault is None:
            self._message = f"{name}: {status.fault}"
            self._notify_event("fault", {"message": self._message, "state": self.state})
        self._reported[name] = (status.failures, status.fault)

    def _sleep_to(self, deadline: float) -> None:
        super()._sleep_to(self._wall_start + self.cycle * self.time_step)

    def _close(self):
        if self._lockstep is not None:
            self._lockstep.wait(0)
            self._lockstep.stop()
        for thread in self.threads:
            thread.stop()
        return super()._close()
