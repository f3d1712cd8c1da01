"""What a run hands its observers: one record per cycle and one per event."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class TaskView:
    """An enabled task as drawn and logged.

    ``kind`` is ``pose``, ``position``, ``orientation``, ``joint``, ``velocity``,
    ``gaze`` or ``force``. ``target`` and ``reference`` (the interpolated target) are 4x4
    homogeneous matrices in the world frame for ``pose`` and ``orientation``, 3-vectors
    [m] for ``position``, joint vectors [rad or m] for ``joint`` and velocity vectors for
    ``velocity``; a ``gaze`` task's target is the watched pose (4x4) and its reference
    the 2-vector of the direction's components across the optical axis; a ``force``
    task's target and reference are its target force [N], world frame. ``error`` is
    the norm of the task error [m, rad or N]; for a ``pose``, ``position_error`` [m] and
    ``orientation_error`` [rad] are its two parts (NaN for other kinds).
    """

    name: str
    kind: str
    body: str | None
    error: float
    target: np.ndarray
    reference: np.ndarray
    position_error: float = float("nan")
    orientation_error: float = float("nan")


@dataclass(slots=True)
class CycleRecord:
    """One control cycle, as seen after the command was written (copies, safe to keep;
    one record is shared by every observer: read it, never modify it).

    ``q`` is the whole world's configuration (pinocchio ``nq``); ``positions`` [rad or
    m] and ``command`` [rad/s or m/s] are the controlled group's, in its joint order.
    ``tasks`` is a sequence of :class:`TaskView`, computed when first read.
    ``body_poses`` gives the 4x4 world pose of environment bodies moved by ``attach``.
    ``state`` is the active configuration (leaf paths joined by `` | ``) after the
    cycle's transitions; ``transitions`` the
    :class:`~robocop_dsl.runtime.statechart.MicroStep` s taken in the cycle (the
    start-up's included in the first). Times are seconds. ``wrenches`` gives, by body,
    each force sensor's reading ``[fx, fy, fz, tx, ty, tz]`` [N, N m] (what the body
    exerts on the environment, world frame); empty when the driver measures none.
    ``variables`` gives each var's value [SI] after the cycle, by qualified name.
    """

    cycle: int
    time: float
    state: str
    q: np.ndarray
    positions: np.ndarray
    command: np.ndarray
    solved: bool
    tasks: Sequence = ()
    body_poses: dict = field(default_factory=dict)
    compute_time: float = 0.0
    cycle_time: float = 0.0
    transitions: tuple = ()
    wrenches: dict = field(default_factory=dict)
    variables: dict = field(default_factory=dict)


@dataclass(frozen=True)
class Event:
    """Something that happened during a run: ``kind`` is one of ``start`` (``state``,
    ``world``: the world file's path), ``transition``, ``action``, ``qp_failure``,
    ``overrun``, ``fault`` (its ``message`` names what failed), ``event``, ``log``,
    ``dropped`` (a writer fell behind: ``writer``, ``cycles``, ``from`` and ``to`` [s]),
    ``end`` (``outcome``, ``state``, ``message``, ``holding``)."""

    kind: str
    time: float
    cycle: int
    data: dict = field(default_factory=dict)

    def to_json(self) -> dict:
        return {"kind": self.kind, "time": self.time, "cycle": self.cycle, **self.data}


class Observer:
    """Watches a run without changing it; every hook is optional.

    ``wants_tasks``: whether ``on_cycle`` reads ``record.tasks``; the runner captures
    the tasks only when an observer wants them.
    """

    wants_tasks = True

    def on_start(self, runner) -> None:
        """Called once before the first cycle."""

    def on_cycle(self, record: CycleRecord) -> None:
        """Called after each cycle; must return quickly (copy, don't compute)."""

    def on_event(self, event: Event) -> None:
        """Called for each event as it happens."""

    def on_stop(self, result) -> None:
        """Called once when the run ends, whatever the reason (after the robot was
        brought to rest), even after this observer raised."""
