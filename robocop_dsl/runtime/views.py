"""Snapshots of the enabled tasks for observers (viewer, log): targets and references
in the world frame."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..control import BodyTarget
from .records import TaskView

_KINDS = {"joint_position": "joint", "joint_velocity": "velocity", "body_velocity": "velocity",
          "body_position": "position", "body_orientation": "orientation", "body_pose": "pose"}


def _in_world(task, value) -> np.ndarray:
    """A task value (pose, rotation, position or vector) as drawn in the world frame."""
    if value is None:
        return np.zeros(0)
    kinematics = task.state.kinematics
    reference = getattr(task, "reference_id", 0)
    frame = kinematics.pose(reference) if reference else None
    if isinstance(value, pin.SE3):
        return (frame * value if frame is not None else value).homogeneous
    value = np.asarray(value, dtype=float)
    if task.kind == "body_orientation":
        pose = np.eye(4)
        pose[:3, :3] = value if frame is None else frame.rotation @ value
        pose[:3, 3] = kinematics.pose(task.body_id).translation
        return pose
    if task.kind == "body_position" and frame is not None:
        return frame.act(value)
    return value.copy()


def _target_value(task):
    target = task.target
    if isinstance(target, BodyTarget):
        return task.value_from_body(task.state, target)
    if not hasattr(target, "shape") and not isinstance(target, pin.SE3):
        return task.reference_value
    return target


def task_views(controller) -> tuple:
    """One :class:`TaskView` per enabled task of ``controller``."""
    views = []
    for task in controller.tasks():
        if not task.enabled:
            continue
        views.append(TaskView(task.name, _KINDS.get(task.kind, task.kind),
                              getattr(task, "body", None), task.error,
                              _in_world(task, _target_value(task)),
                              _in_world(task, task.reference_value)))
    return tuple(views)
