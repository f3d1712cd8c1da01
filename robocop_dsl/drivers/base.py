"""The base of drivers whose robot side runs in its own thread.

The controller thread calls ``connect()``, then ``read()`` at the start of each cycle
and ``write()`` (or ``hold()``) at its end, then ``disconnect()``. ``read()`` and
``write()`` only copy through an :class:`AsyncWorldWriter` / :class:`AsyncWorldReader`
pair; the driver thread runs :meth:`ThreadedDriver._serve` on the other side.
"""

from __future__ import annotations

import threading
import time

import numpy as np

from .buffers import AsyncWorldReader, AsyncWorldWriter, JointState
from .errors import DriverFault

DEFAULT_COMMAND_TIMEOUT = 0.05
DEFAULT_STATE_TIMEOUT = 0.25
DEFAULT_CONNECT_TIMEOUT = 5.0


class ThreadedDriver:
    """A driver whose robot side runs in a thread of its own.

    Subclasses implement :meth:`_open`, :meth:`_serve` and :meth:`_close`; ``_serve``
    publishes states with ``self.writer.sync(...)``, takes commands with
    ``self.reader.sync()`` and returns once ``self._stop`` is set. An exception leaving
    ``_serve`` becomes the driver's fault: the next ``read()``/``write()`` raises it.

    Args:
        world: The world (its model gives the configuration space).
        joint_group: The driven group's name.
        state_timeout: ``read()`` raises :class:`DriverFault` when the latest state is
            older than this [s].
        connect_timeout: Longest wait for the first state in ``connect()`` [s].
        initial: Configuration (nq) used outside the group; defaults to the world's
            ``initial:``.
        sensors: The bodies of the force sensors whose wrenches the robot side
            publishes with each state.
    """

    realtime = True
    """The robot side follows the wall clock: the control loop must run in real time."""

    def __init__(self, world, joint_group: str, state_timeout: float = DEFAULT_STATE_TIMEOUT,
                 connect_timeout: float = DEFAULT_CONNECT_TIMEOUT,
                 initial: np.ndarray | None = None, sensors: tuple = ()):
        self.world = world
        self.model = world.model
        self.group = world.joint_group(joint_group)
        self.state_timeout = float(state_timeout)
        self.connect_timeout = float(connect_timeout)
        self.initial = np.array(world.initial_configuration() if initial is None else initial,
                                dtype=float)
        self.sensors = tuple(sensors)
        self.reader = AsyncWorldReader(self.group)
        self.writer = AsyncWorldWriter(self.group, wrenches=len(self.sensors))
        self.last_state: JointState | None = None
        self._q = self.initial.copy()
        self._v = np.zeros(self.model.nv)
        self._stop = threading.Event()
        self._first_state = threading.Event()
        self._thread: threading.Thread | None = None
        self._fault: str | None = None

    def __enter__(self):
        self.connect()
        return self

    def __exit__(self, *exc) -> None:
        self.disconnect()

    @property
    def connected(self) -> bool:
        """Whether the driver thread is running."""
        return self._thread is not None and self._thread.is_alive()

    @property
    def fault(self) -> str | None:
        """Why the robot stopped answering, or ``None``."""
        return self._fault

    def connect(self) -> None:
        """Open the robot and start the driver thread; return once a first state arrived.

        Raises:
            DriverFault: The robot cannot be reached or sent no state in
                ``connect_timeout``.
        """
        if self._thread is not None:
            return
        self._fault = None
        self._stop.clear()
        self._first_state.clear()
        self._open()
        self._thread = threading.Thread(target=self._run, name=f"driver {self.group.name}",
                                        daemon=True)
        self._thread.start()
        if not self._first_state.wait(self.connect_timeout) or self._fault is not None:
            reason = self._fault or f"no state within {self.connect_timeout:g} s"
            self.disconnect()
            raise DriverFault(repr(self), reason)

    def disconnect(self) -> None:
        """Stop the driver thread and close the robot; safe to call twice."""
        if self._thread is None:
            return
        self._stop.set()
        self._thread.join()
        self._thread = None
        self._close()
        self.reader.release_sync()
        self.writer.release_sync()

    def read(self) -> tuple:
        """The robot's latest state written into a copy of the world's configuration.

        Returns:
            ``(q, v)``: configuration (nq) and velocity (nv) of the whole world, the
            group's coordinates from the robot, the others from ``initial``.

        Raises:
            DriverFault: Not connected, the driver thread stopped, or the latest state
                is older than ``state_timeout``.
        """
        self._check()
        state = self.writer.write(self._q, self._v)
        age = time.monotonic() - state.time
        if age > self.state_timeout:
            raise DriverFault(repr(self), f"no state from the robot for {age:.3f} s "
                                          f"(state timeout {self.state_timeout:g} s)")
        self.last_state = state
        return self._q.copy(), self._v.copy()

    def write(self, velocity: np.ndarray) -> None:
        """Command the group's joint velocities [rad/s or m/s] (``group.dofs``).

        Raises:
            DriverFault: Not connected or the driver thread stopped.
        """
        self._check()
        self.reader.read(velocity)

    def hold(self) -> None:
        """Command zero velocity."""
        self.write(np.zeros(self.group.dofs))

    def _check(self) -> None:
        if self._fault is not None:
            raise DriverFault(repr(self), self._fault)
        if self._thread is None:
            raise DriverFault(repr(self), "not connected (call connect() first)")

    def _run(self) -> None:
        try:
            self._serve()
        except Exception as error:  # the thread's end must reach the controller thread
            self._fault = self._describe(error)
            self._first_state.set()

    def _publish(self, position, velocity, holding: bool, stamp: float,
                 wrenches=()) -> None:
        """Publish a state (and the wrench of each of :attr:`sensors`) from the driver
        thread and release a waiting ``connect()``."""
        self.writer.sync(position, velocity, holding, stamp, wrenches)
        self._first_state.set()

    def _describe(self, error: Exception) -> str:
        """The fault message for an exception that ended the driver thread."""
        return f"driver thread stopped: {type(error).__name__}: {error}"

    def _open(self) -> None:
        """Reach the robot (controller thread, before the driver thread starts)."""

    def _serve(self) -> None:
        """The driver thread's loop; returns when ``self._stop`` is set."""
        raise NotImplementedError

    def _close(self) -> None:
        """Release the robot (after the driver thread ended)."""
