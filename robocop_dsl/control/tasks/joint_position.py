"""The ``joint_position`` task: drive a joint group to target positions."""

from __future__ import annotations

import numpy as np

from ..state import ControlState
from .base import Task


class JointPositionTask(Task):
    """Joint positions of a group [rad or m], in the group's joint order.

    Args:
        name: The task's name.
        state: The controller's state.
        group: The joint group (inside the controlled group).
        **parameters: Those of :class:`Task`.
    """

    kind = "joint_position"

    def __init__(self, name: str, state: ControlState, group: str, **parameters):
        self.group, self.columns = state.group_columns(group)
        self._positions = state.q_indices[self.columns]
        self._jacobian = np.eye(state.dofs)[self.columns]
        super().__init__(name, state, len(self.columns), **parameters)

    def compute_value(self, state: ControlState) -> np.ndarray:
        return state.q[self._positions]

    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        return self._jacobian

    def describe(self) -> str:
        return f"group={self.group.name!r}, "
