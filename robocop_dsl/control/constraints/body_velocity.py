"""The ``body_velocity`` constraint: bound a body's linear and angular speed."""

from __future__ import annotations

import numpy as np

from ..exceptions import UnknownName
from ..parameters import vector_parameter
from ..state import ControlState
from .base import Constraint

_DIRECTIONS = np.array([
    (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (1, -1, 0), (1, 0, 1), (1, 0, -1),
    (0, 1, 1), (0, 1, -1), (1, 1, 1), (1, 1, -1), (1, -1, 1), (-1, 1, 1)], dtype=float)
_DIRECTIONS /= np.linalg.norm(_DIRECTIONS, axis=1)[:, None]
INSCRIBED_SCALE = 1.0 / 1.1280928107595818
"""``{v : |d.v| <= s}`` over the 13 directions lies in the ball of radius 1 for
``s = INSCRIBED_SCALE``: 1.128... is the polytope's largest vertex norm for ``s = 1``."""


class BodyVelocityConstraint(Constraint):
    """Bounds the velocity of a body, relative to a reference, in its axes.

    A scalar limit bounds the speed (Euclidean norm) through 13 symmetric direction
    pairs (cube axes, face and body diagonals), which keep the speed at most the limit
    and allow at least 88.6% of it in every direction. A 3-vector limit bounds each
    axis of the reference frame separately.

    Args:
        name: The constraint's name.
        state: The controller's state.
        body: The constrained body.
        reference: The frame velocities are measured in (default ``world``).
        max_linear: Linear speed limit of the body's origin [m/s], scalar or per axis.
        max_angular: Angular speed limit [rad/s], scalar or per axis.
    """

    kind = "body_velocity"

    def __init__(self, name: str, state: ControlState, body: str, *, reference: str = "world",
                 max_linear=np.inf, max_angular=np.inf):
        super().__init__(name, state)
        self.body = body
        self.reference = reference
        self.body_id = state.body(body)
        self.reference_id = 0 if reference == "world" else state.body(reference)
        self.max_linear = max_linear
        self.max_angular = max_angular

    @staticmethod
    def _shape(limit: np.ndarray, scalar: bool) -> tuple[np.ndarray, np.ndarray]:
        if scalar:
            rows = _DIRECTIONS if np.isfinite(limit[0]) else np.zeros((0, 3))
            return rows, np.full(len(rows), limit[0] * INSCRIBED_SCALE)
        finite = np.isfinite(limit)
        return np.eye(3)[finite], limit[finite]

    def _set(self, name: str, value) -> None:
        scalar = np.ndim(value) == 0
        limit = vector_parameter(self.label, name, value, 1 if scalar else 3, minimum=0.0,
                                 allow_inf=True)
        setattr(self, f"_{name}", float(limit[0]) if scalar else limit)
        setattr(self, f"_{name}_rows", self._shape(limit, scalar))
        self._selection = None
        self.state.revision += 1

    @property
    def max_linear(self):
        """Linear speed limit [m/s] (scalar: norm; 3-vector: per axis)."""
        return self._max_linear

    @max_linear.setter
    def max_linear(self, value) -> None:
        self._set("max_linear", value)

    @property
    def max_angular(self):
        """Angular speed limit [rad/s] (scalar: norm; 3-vector: per axis)."""
        return self._max_angular

    @max_angular.setter
    def max_angular(self, value) -> None:
        self._set("max_angular", value)

    def _rows(self) -> tuple[np.ndarray, np.ndarray]:
        if self._selection is None:
            linear, linear_bound = self._max_linear_rows
            angular, angular_bound = self._max_angular_rows
            selection = np.zeros((len(linear) + len(angular), 6))
            selection[:len(linear), :3] = linear
            selection[len(linear):, 3:] = angular
            self._selection = (selection, np.concatenate((linear_bound, angular_bound)))
        return self._selection

    @property
    def rows(self) -> int:
        return len(self._rows()[1])

    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        return self._rows()[0] @ state.jacobian(self.body_id, self.reference_id)

    def compute_bounds(self, state: ControlState) -> tuple[np.ndarray, np.ndarray]:
        bound = self._rows()[1]
        return -bound, bound

    def write_rows(self, state: ControlState, jacobian: np.ndarray, lower: np.ndarray,
                   upper: np.ndarray) -> None:
        """The rows and bounds straight into the QP's arrays."""
        selection, bound = self._rows()
        np.negative(bound, out=lower)
        upper[:] = bound
        np.dot(selection, state.jacobian(self.body_id, self.reference_id), out=jacobian)

    def parameters(self) -> dict:
        return {"reference": self.reference, "max_linear": self._max_linear,
                "max_angular": self._max_angular}

    def configure(self, **parameters) -> None:
        unknown = set(parameters) - {"max_linear", "max_angular"}
        if unknown:
            raise UnknownName("parameter of body_velocity", sorted(unknown)[0],
                              ["max_linear", "max_angular"])
        super().configure(**parameters)

    def describe(self) -> str:
        return f"body={self.body!r}, "
