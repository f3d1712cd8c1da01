"""Snapshots of the enabled tasks for observers (viewer, log): targets and references
in the world frame.

In the loop, :func:`task_views` only keeps references: each enabled task's
:class:`~robocop_dsl.control.TaskSample` (what the controller computed for it that
cycle), its target, and the mapping of world poses computed at that state. The error
norms and the world-frame values are computed when an observer first reads the views,
which observers that keep records do after the run; the log's writing process computes
them from the captures (:mod:`~robocop_dsl.runtime.record_batch`), with copies of the
tasks (:meth:`~robocop_dsl.control.Task.detached`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from ..control.tasks.base import Task
from .records import TaskView

_LINEAR, _ANGULAR = slice(0, 3), slice(3, 6)     # of a pose task's error
_KINDS = {"joint_position": "joint", "joint_velocity": "velocity", "body_velocity": "velocity",
          "body_position": "position", "body_orientation": "orientation", "body_pose": "pose",
          "body_force": "force"}
_NOTHING = np.zeros(0)
_NOTHING.flags.writeable = False
_ORIGIN = pin.SE3.Identity()


class TaskViews(Sequence):
    """The :class:`TaskView` of each enabled task of one cycle, computed on first read
    (from any thread)."""

    __slots__ = ("_captures", "_views")

    def __init__(self, captures: tuple):
        self._captures = captures
        self._views = None

    def _resolved(self) -> tuple:
        views = self._views
        if views is None:
            views = self._views = tuple(resolve_view(*capture) for capture in self._captures)
        return views

    @property
    def captures(self) -> tuple:
        """``(task, sample, target, poses)`` of each view, as :func:`task_views` kept them."""
        return self._captures

    def __add__(self, other: TaskViews) -> TaskViews:
        return TaskViews(self._captures + other._captures)

    def __getitem__(self, index):
        return self._resolved()[index]

    def __len__(self) -> int:
        return len(self._captures)

    def __iter__(self):
        return iter(self._resolved())

    def __repr__(self) -> str:
        return f"TaskViews({list(self._resolved())!r})"


def view_kind(task) -> str:
    """The :class:`TaskView` kind of a task (``pose`` for a ``body_pose`` task...)."""
    return _KINDS.get(task.kind, task.kind)


def view_kinds(tasks) -> tuple:
    """``(name, kind)`` of each view of ``tasks``: a :class:`TaskViews` (read without
    computing its views) or any sequence of :class:`TaskView`."""
    if isinstance(tasks, TaskViews):
        return tuple((capture[0].name, view_kind(capture[0])) for capture in tasks.captures)
    return tuple((view.name, view.kind) for view in tasks)


def task_views(controller) -> TaskViews:
    """The enabled tasks of ``controller`` at its latest state."""
    poses = controller.kinematics.poses()
    return TaskViews(tuple([(task, task.sample(), task.target, poses)
                            for task in controller.tasks() if task.enabled]))


def frames_read(task, target) -> list:
    """The frames whose world poses :func:`resolve_view` reads for ``task``, with
    ``target``, when the task has a value: its reference body, its body for a gaze or an
    orientation, and the body a gaze watches (asked of the task itself)."""
    reference_id = getattr(task, "reference_id", 0)
    read = [reference_id] if reference_id else []
    kind = view_kind(task)
    if kind in ("gaze", "orientation"):
        read.append(task.body_id)
    if kind == "gaze":
        task.locate(target, lambda frame_id: read.append(frame_id) or _ORIGIN)
    return read


def resolve_view(task, sample, target, poses: dict) -> TaskView:
    """A task's view from what was captured in its cycle: its
    :class:`~robocop_dsl.control.TaskSample`, its target and the world poses by frame id
    (at least those of :func:`frames_read`)."""
    kind = view_kind(task)
    body = getattr(task, "body", None)
    value = sample.value
    if value is None:
        return TaskView(task.name, kind, body, math.nan, _NOTHING, _NOTHING)
    reference_id = getattr(task, "reference_id", 0)
    frame = poses[reference_id] if reference_id else None
    if kind == "gaze":
        pose = _relative(poses[task.body_id], frame)
        watched = task.locate(target, lambda frame_id: _relative(poses[frame_id], frame))
        shown = _NOTHING if watched is None else _in_world(task, watched, frame, None)
        return TaskView(task.name, kind, body, task.angle_at(pose, watched), shown,
                        _in_world(task, sample.reference, frame, None))
    goal = sample.goal
    body_pose = poses[task.body_id] if kind == "orientation" else None
    if kind == "pose":
        error = task.compute_error(value, goal)
        linear, angular = error[_LINEAR], error[_ANGULAR]
        parts = (math.sqrt(linear @ linear), math.sqrt(angular @ angular))
        norm = (math.hypot(*parts) if type(task).error_norm is Task.error_norm
                else task.error_norm(value, goal))
        return TaskView(task.name, kind, body, norm, _in_world(task, goal, frame, body_pose),
                        _in_world(task, sample.reference, frame, body_pose), *parts)
    return TaskView(task.name, kind, body, task.error_norm(value, goal),
                    _in_world(task, goal, frame, body_pose),
                    _in_world(task, sample.reference, frame, body_pose))


def _relative(pose: pin.SE3, frame: pin.SE3 | None) -> pin.SE3:
    return pose if frame is None else frame.actInv(pose)


def _in_world(task, value, frame: pin.SE3 | None, body: pin.SE3 | None) -> np.ndarray:
    """A task value (pose, rotation, position or vector) as drawn in the world frame;
    ``frame`` is the reference body's world pose (``None``: the world) and ``body`` the
    controlled body's world pose (where an orientation is drawn)."""
    if value is None:
        return _NOTHING
    if isinstance(value, pin.SE3):
        return (frame * value if frame is not None else value).homogeneous
    if task.kind == "body_orientation":
        pose = np.eye(4)
        pose[:3, :3] = value if frame is None else frame.rotation @ value
        pose[:3, 3] = body.translation
        return pose
    if frame is not None and task.kind == "body_position":
        return frame.act(value)
    return np.array(value, dtype=float)
