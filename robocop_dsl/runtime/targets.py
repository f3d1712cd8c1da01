"""Compiled targets (SI specs) to the controller's target values."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..compile import spec as s
from ..control import CURRENT, BodyTarget


def control_target(task, target: s.TargetSpec):
    """The value to assign to ``task.target`` for a compiled target.

    Unconstrained parts of a ``pose(...)`` keep the task's current value.
    """
    if isinstance(target, s.CurrentTarget):
        return CURRENT
    if isinstance(target, s.BodyTarget):
        offset = None if target.offset is None else np.array(target.offset, dtype=float)
        return BodyTarget(target.body, offset)
    if isinstance(target, s.PoseTarget):
        return _pose(task, target)
    values = np.array(target.values, dtype=float)
    if task.kind == "body_orientation" and values.shape == (3,):
        return pin.rpy.rpyToMatrix(*values)
    return values


def _pose(task, target: s.PoseTarget):
    current = task.pose(task.state) if task.state.kinematics.q is not None else pin.SE3.Identity()
    rotation = (pin.rpy.rpyToMatrix(*target.rpy) if target.rpy is not None
                else current.rotation.copy())
    position = (np.array(target.position, dtype=float) if target.position is not None
                else current.translation.copy())
    if task.kind == "body_position":
        return position
    if task.kind == "body_orientation":
        return rotation
    return pin.SE3(rotation, position)
