"""The stop as a QP: the velocity brought to zero as fast as the acceleration limits
allow, under every enabled constraint.

``min |dq|^2`` over the box met with the acceleration limits around the previous
command is, joint by joint, the previous command moved towards zero by
``max_acceleration * dt``; the constraints' rows (collision dampers, body velocity
bounds, position limits) stay hard, so a stop never drives through an obstacle or past
a limit.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ..control.solvers.base import QPSolver

SETTLING_TIME = 1.0
"""[s] How long a stop may go on past the time its braking needs at the acceleration
limits (a constraint pushing the robot back within a limit), before the robot holds."""
AT_REST = 1e-6
"""A command whose every entry is below this [rad/s or m/s] is a stop's last one."""


class BrakingProgram:
    """The braking QP over a hierarchy's constraint arrays (shared, not copied).

    Args:
        hierarchy: The :class:`~robocop_dsl.control.hierarchy.Hierarchy` whose ``C``,
            ``l``, ``u``, ``lower`` and ``upper`` the controller writes every cycle.
        solver: The solver, kept between cycles (warm starts).
    """

    def __init__(self, hierarchy, solver: QPSolver):
        from ..control.solvers.base import QuadraticProgram   # the controller imports this

        n = hierarchy.lower.shape[0]
        self.program = QuadraticProgram(np.eye(n), np.zeros(n), np.zeros((0, n)), np.zeros(0),
                                        hierarchy.C, hierarchy.l, hierarchy.u, hierarchy.lower,
                                        hierarchy.upper)
        self.solver = solver

    def solve(self) -> np.ndarray | None:
        """The braking command [rad/s or m/s] (entries below :data:`AT_REST` made zero
        where the box holds zero), or ``None`` when the constraints have no common
        solution."""
        program = self.program
        solution = self.solver.solve(program)
        x = solution.x
        if not solution.found or not np.all(np.isfinite(x)):
            return None
        if not self.solver.guarantees_tolerance and program.violation(x) > 1e-6:
            return None
        x[(np.abs(x) < AT_REST) & (program.lower <= 0.0) & (program.upper >= 0.0)] = 0.0
        return x


def stop_cycles(limits, command: np.ndarray, time_step: float) -> int:
    """The most cycles a stop from ``command`` [rad/s or m/s] may take: its braking at
    the acceleration limits of ``limits`` (a
    :class:`~robocop_dsl.safety.limits.JointLimits`, or ``None``), then
    :data:`SETTLING_TIME`."""
    braking = 0.0
    if limits is not None:
        with np.errstate(divide="ignore", invalid="ignore"):
            steps = np.abs(command) / (limits.max_acceleration * time_step)
        braking = float(np.max(np.nan_to_num(steps, posinf=0.0), initial=0.0))
    return math.ceil(braking + SETTLING_TIME / time_step)
