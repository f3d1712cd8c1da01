"""The ``joint_position`` task: drive a joint group to target positions."""

from __future__ import annotations

import numpy as np

from ..spatial import JointChart
from ..state import ControlState
from .base import Task


class JointPositionTask(Task):
    """Joint positions of a group [rad or m], one per dof, in the group's joint order.

    A continuous joint's position is its angle; its target is reached the shortest way
    round (from 10 deg, a target of 350 deg is 20 deg away), and its error is the
    shortest turn to the target.

    Args:
        name: The task's name.
        state: The controller's state.
        group: The joint group (inside the controlled group).
        **parameters: Those of :class:`Task`.
    """

    kind = "joint_position"

    def __init__(self, name: str, state: ControlState, group: str, **parameters):
        self.group, self.columns = state.group_columns(group)
        self._jacobian = np.eye(state.dofs)[self.columns]
        self._wraps = bool(self.group.space.continuous.any())
        super().__init__(name, state, len(self.columns), **parameters)

    def compute_value(self, state: ControlState) -> np.ndarray:
        return state.group_positions[self.columns]

    def compute_error(self, value, reference) -> np.ndarray:
        if self._wraps:
            return self.group.space.difference(value, reference)
        return reference - value

    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        return self._jacobian

    def chart_for(self, value):
        if self._wraps:
            return JointChart(self.group.space, value.copy())
        return super().chart_for(value)

    def describe(self) -> str:
        return f"group={self.group.name!r}, "
