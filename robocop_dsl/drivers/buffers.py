"""Copies between a world, owned by one controller thread, and a driver thread.

RoboCoP's rule: a world is touched by its controller thread only. A driver thread
never sees the world; it exchanges copies through two buffers:

- :class:`AsyncWorldReader` reads the group's command out of the world: the controller
  thread calls ``read(velocity)``, the driver thread ``sync()`` to get the latest one;
- :class:`AsyncWorldWriter` writes the robot's state into the world: the driver thread
  calls ``sync(position, velocity)``, the controller thread ``write(q, v)``.

Each buffer is double-buffered: the producer fills a back slot without the lock, then
swaps it to the front under the lock; the consumer copies the front under the lock.
Neither side waits longer than one copy of the group's vectors, and a consumer always
gets every value from the same producer cycle.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field

import numpy as np

from .errors import ThreadOwnershipError


@dataclass(frozen=True)
class JointState:
    """A joint group's state as one driver cycle measured it.

    Attributes:
        sequence: Number of the driver cycle that produced it (1 for the first).
        time: When it was produced [s], ``time.monotonic()`` of this process.
        position: The group's configuration coordinates (``len(group.q_indices)``;
            a continuous joint has two) [rad or m].
        velocity: The group's joint velocities (``group.dofs``) [rad/s or m/s].
        holding: Whether the driver was holding (no fresh command) in that cycle.
        wrenches: One ``[fx, fy, fz, tx, ty, tz]`` [N, N m] per force sensor the robot
            reports (what its body exerts on the environment, world frame); none when
            it reports none.
    """

    sequence: int
    time: float
    position: np.ndarray
    velocity: np.ndarray
    holding: bool = False
    wrenches: np.ndarray = field(default_factory=lambda: np.zeros((0, 6)))


@dataclass(frozen=True)
class JointCommand:
    """A joint group's velocity command as one controller cycle wrote it.

    Attributes:
        sequence: Number of the controller write (1 for the first).
        time: When it was written [s], ``time.monotonic()`` of this process.
        velocity: The group's joint velocities (``group.dofs``) [rad/s or m/s].
    """

    sequence: int
    time: float
    velocity: np.ndarray


class _ThreadSide:
    """One side of a buffer, claimed by the first thread that uses it."""

    def __init__(self):
        self._thread: threading.Thread | None = None
        self._claim = threading.Lock()

    def check(self, buffer: str, method: str) -> None:
        current = threading.current_thread()
        if self._thread is current:
            return
        with self._claim:
            if self._thread is None:
                self._thread = current
                return
        raise ThreadOwnershipError(buffer, method, self._thread.name, current.name)

    def release(self) -> None:
        with self._claim:
            self._thread = None


class _DoubleBuffer:
    """Two slots of named float vectors plus a stamp; see the module docstring."""

    def __init__(self, sizes: dict):
        self._slots = [{k: np.zeros(n) for k, n in sizes.items()} for _ in range(2)]
        self._stamps = [None, None]
        self._front = 0
        self._lock = threading.Lock()

    def publish(self, values: dict, stamp: tuple) -> None:
        back = 1 - self._front
        slot = self._slots[back]
        for key, value in values.items():
            np.copyto(slot[key], value)
        with self._lock:
            self._stamps[back] = stamp
            self._front = back

    def snapshot(self) -> tuple | None:
        with self._lock:
            stamp = self._stamps[self._front]
            if stamp is None:
                return None
            arrays = {k: v.copy() for k, v in self._slots[self._front].items()}
        return arrays, stamp


def _vector(value, size: int, what: str, owner: str) -> np.ndarray:
    array = np.asarray(value, dtype=float)
    if array.shape != (size,):
        raise ValueError(f"{owner}: {what} must have shape ({size},), got {array.shape}")
    return array


def _frozen(array: np.ndarray) -> np.ndarray:
    array.flags.writeable = False
    return array


class AsyncWorldReader:
    """Carries a joint group's velocity command from the world to a driver thread.

    Args:
        group: The driven :class:`~robocop_dsl.world.world.JointGroup`.
        clock: Time source [s] for the command stamps.
    """

    def __init__(self, group, clock=time.monotonic):
        self.group = group
        self._clock = clock
        self._buffer = _DoubleBuffer({"velocity": group.dofs})
        self._owner = _ThreadSide()
        self._driver = _ThreadSide()
        self._sequence = 0

    def __repr__(self) -> str:
        return f"AsyncWorldReader({self.group.name}, {self.group.dofs} dofs)"

    def read(self, velocity) -> JointCommand:
        """Copy the group's command out of the world; controller thread only.

        Args:
            velocity: The group's joint velocities (``group.dofs``) [rad/s or m/s].

        Returns:
            The command as stamped and published.

        Raises:
            ThreadOwnershipError: Called from another thread than the world's.
            ValueError: ``velocity`` has the wrong shape.
        """
        self._owner.check(repr(self), "read")
        array = _vector(velocity, self.group.dofs, "velocity", repr(self))
        self._sequence += 1
        now = self._clock()
        self._buffer.publish({"velocity": array}, (self._sequence, now))
        return JointCommand(self._sequence, now, _frozen(array.copy()))

    def sync(self) -> JointCommand | None:
        """The latest command (a copy), or ``None`` before the first; driver thread only."""
        self._driver.check(repr(self), "sync")
        snapshot = self._buffer.snapshot()
        if snapshot is None:
            return None
        arrays, (sequence, stamp) = snapshot
        return JointCommand(sequence, stamp, _frozen(arrays["velocity"]))

    def release_sync(self) -> None:
        """Let another driver thread call :meth:`sync` (after the previous one ended)."""
        self._driver.release()


class AsyncWorldWriter:
    """Carries a joint group's state from a driver thread into the world.

    Args:
        group: The driven :class:`~robocop_dsl.world.world.JointGroup`.
        clock: Time source [s] for the state stamps.
        wrenches: How many force sensors' wrenches each state carries.
    """

    def __init__(self, group, clock=time.monotonic, wrenches: int = 0):
        self.group = group
        self._clock = clock
        self._nq = len(group.q_indices)
        self.wrenches = wrenches
        self._buffer = _DoubleBuffer({"position": self._nq, "velocity": group.dofs,
                                      "holding": 1, "wrenches": 6 * wrenches})
        self._owner = _ThreadSide()
        self._driver = _ThreadSide()
        self._sequence = 0

    def __repr__(self) -> str:
        return f"AsyncWorldWriter({self.group.name}, {self.group.dofs} dofs)"

    def sync(self, position, velocity, holding: bool = False,
             stamp: float | None = None, wrenches=()) -> int:
        """Publish the robot's latest state; driver thread only.

        Args:
            position: The group's coordinates (``len(group.q_indices)``) [rad or m].
            velocity: The group's joint velocities (``group.dofs``) [rad/s or m/s].
            holding: Whether the driver is holding for lack of a fresh command.
            stamp: When it was measured [s]; defaults to now.
            wrenches: The force sensors' wrenches (:attr:`wrenches` x 6) [N, N m].

        Returns:
            The state's sequence number.
        """
        self._driver.check(repr(self), "sync")
        values = {"position": _vector(position, self._nq, "position", repr(self)),
                  "velocity": _vector(velocity, self.group.dofs, "velocity", repr(self)),
                  "holding": float(holding),
                  "wrenches": _vector(np.ravel(wrenches), 6 * self.wrenches, "wrenches",
                                      repr(self))}
        self._sequence += 1
        self._buffer.publish(values, (self._sequence, self._clock() if stamp is None
                                      else stamp))
        return self._sequence

    def write(self, q: np.ndarray, v: np.ndarray) -> JointState | None:
        """Write the latest state into the world's ``q`` (nq) and ``v`` (nv), in place.

        Controller thread only. Coordinates outside the group are left untouched.

        Returns:
            The state written, or ``None`` (and nothing written) before the first sync.

        Raises:
            ThreadOwnershipError: Called from another thread than the world's.
        """
        self._owner.check(repr(self), "write")
        snapshot = self._buffer.snapshot()
        if snapshot is None:
            return None
        arrays, (sequence, stamp) = snapshot
        q[self.group.q_indices] = arrays["position"]
        v[self.group.v_indices] = arrays["velocity"]
        return JointState(sequence, stamp, _frozen(arrays["position"]),
                          _frozen(arrays["velocity"]), bool(arrays["holding"][0]),
                          _frozen(arrays["wrenches"].reshape(-1, 6)))

    def release_sync(self) -> None:
        """Let another driver thread call :meth:`sync` (after the previous one ended)."""
        self._driver.release()
