"""Relax, never give up: when the hard set of a cycle has no common command, slack is
added in a fixed order and minimised:

1. ``body_velocity`` bounds;
2. the acceleration limits (the mission's and the world's).

Lexicographically, in two QPs: first the acceleration limits' slack, the
``body_velocity`` bounds all but free; then the bounds' slack, within the acceleration
limits so relaxed.

Position limits, the URDF's speed limits and collision distances are never traded
away, except to allow what the current state already does: a joint past a position
limit, or a pair closer than its ``min_distance``, may then stay where it is (zero
velocity) instead of being driven back. Each relaxation is a :class:`Relaxation`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ..control.solvers.base import QuadraticProgram

FREE_WEIGHT = 1e-6
"""Weight of the squared slack of ``body_velocity`` rows while the acceleration limits'
slack is minimised (against 1): they are relaxed first."""
COMMAND_WEIGHT = 1e-3
"""Weight of ``|dq - previous|^2``, keeping the relaxation QP strictly convex."""
RELAXATION_TOLERANCE = 1e-9
"""ProxQP's tolerance on the relaxation QP [command units]."""
MARGIN = 1e-6
"""Slack at or below this is none; above it, this is added to the slack before the
relaxed bounds are applied [command units]."""


@dataclass(frozen=True)
class Relaxation:
    """A constraint relaxed in one cycle.

    Attributes:
        constraint: The constraint's label (or the joint limits' owner).
        rows: The relaxed rows: joint names, or row indices of the constraint.
        amount: The largest slack, in ``unit``.
        unit: ``m/s``, ``rad/s`` (rows of velocity), ``rad/s^2`` (acceleration limits),
            or ``held`` (a promise already broken by the state: not made worse).
    """

    constraint: str
    rows: tuple
    amount: float
    unit: str

    def as_event(self) -> dict:
        """The ``constraint_relaxed`` event's data."""
        return {"constraint": self.constraint, "rows": list(self.rows),
                "amount": self.amount, "unit": self.unit}


def acceleration_box(previous: np.ndarray, limits, time_step: float, lower: np.ndarray,
                     upper: np.ndarray, joints) -> list[Relaxation]:
    """Intersect the box ``[lower, upper]`` [rad/s or m/s] with the acceleration limits
    around the ``previous`` command, in place. A joint whose box does not meet them gets
    the velocity closest to ``previous`` within its box: its acceleration limit is
    relaxed by the smallest amount, and reported (``joints`` names the dofs)."""
    step = limits.max_acceleration * time_step
    low, high = previous - step, previous + step
    apart = np.greater(low, upper)
    apart |= np.less(high, lower)
    relaxed = []
    if apart.any():
        apart = np.flatnonzero(apart)
        closest = np.clip(previous[apart], lower[apart], upper[apart])
        low[apart] = high[apart] = closest
        excess = np.abs(closest - previous[apart]) / time_step - limits.max_acceleration[apart]
        owners = [limits.owners[i] for i in apart]
        for owner in sorted(set(owners)):
            mine = [k for k, name in enumerate(owners) if name == owner]
            relaxed.append(Relaxation(owner, tuple(joints[apart[k]] for k in mine),
                                      float(excess[mine].max()), "rad/s^2"))
    np.maximum(lower, low, out=lower)
    np.minimum(upper, high, out=upper)
    return relaxed


@dataclass(frozen=True)
class RowGroup:
    """Rows of the program's ``C`` that belong to one constraint.

    Attributes:
        label: The constraint's label.
        rows: Its rows in the program (a slice).
        relaxable: Whether slack may be added (``body_velocity``).
        unit: The rows' unit.
    """

    label: str
    rows: slice
    relaxable: bool
    unit: str


class Relaxer:
    """Finds the smallest relaxation of a program's constraints (see the module) and
    writes the relaxed bounds into it.

    Args:
        max_iter: The relaxation QP's iteration limit.
    """

    def __init__(self, max_iter: int = 1000):
        self.max_iter = max_iter

    def relax(self, program: QuadraticProgram, hard: tuple[np.ndarray, np.ndarray],
              previous: np.ndarray, limits, time_step: float, groups: list[RowGroup],
              joints) -> tuple[np.ndarray, list[Relaxation]] | None:
        """Relax ``program`` in place; returns a command that meets the relaxed set and
        the relaxations, or ``None`` when even the least demanding set has no solution
        (only for non-finite input).

        Args:
            program: The program whose ``C``, ``l``, ``u``, ``lower`` and ``upper`` hold
                the cycle's constraints (``lower``/``upper``: the hard box met with the
                acceleration limits).
            hard: The box without the acceleration limits [rad/s or m/s].
            previous: The previous command [rad/s or m/s].
            limits: The :class:`~robocop_dsl.safety.limits.JointLimits`.
            time_step: The control period [s].
            groups: The constraints' rows.
            joints: The dofs' names.
        """
        hard_lower, hard_upper = hard[0].copy(), hard[1].copy()
        steps = limits.max_acceleration * time_step
        held: list[Relaxation] = []
        found = self._solve(program, hard_lower, hard_upper, previous, groups, steps, True)
        if found is None:
            held = _hold_what_is_broken(program, hard_lower, hard_upper, groups, joints)
            found = self._solve(program, hard_lower, hard_upper, previous, groups, steps,
                                True)
            if found is None:
                return None
        acceleration_slack = found[1]
        steps = steps + np.where(acceleration_slack > MARGIN, acceleration_slack + MARGIN, 0.0)
        found = self._solve(program, hard_lower, hard_upper, previous, groups, steps, False)
        if found is None:
            return None
        command, body_slack = found
        relaxations = held + self._apply(program, hard_lower, hard_upper, previous, limits,
                                         time_step, groups, joints, body_slack,
                                         acceleration_slack, steps)
        return command, relaxations

    def _solve(self, program, hard_lower, hard_upper, previous, groups, steps,
               acceleration_first: bool):
        """One stage of the relaxation QP, over the command and slack variables; its
        command and slack, or ``None`` when it has no solution.

        ``acceleration_first``: the acceleration limits (``steps`` [rad/s or m/s] around
        ``previous``) get slack, the body rows are all but free; the slack of the
        acceleration limits is returned. Otherwise the acceleration limits (``steps``
        widened by the first stage's slack) hold and the body rows get slack, which is
        returned.
        """
        from ..control.solvers.base import QuadraticProgram   # the controller imports this
        from ..control.solvers.proxqp import ProxqpSolver

        n = program.g.shape[0]
        relaxable = np.zeros(program.l.shape[0], dtype=bool)
        for group in groups:
            relaxable[group.rows] = group.relaxable
        body_rows, hard_rows = np.flatnonzero(relaxable), np.flatnonzero(~relaxable)
        accelerated = np.flatnonzero(np.isfinite(steps))
        m_b = len(body_rows)
        m_a = len(accelerated) if acceleration_first else 0
        size = n + m_b + m_a
        weights = (FREE_WEIGHT, 1.0) if acceleration_first else (1.0, 1.0)
        hessian = np.diag(np.concatenate((np.full(n, COMMAND_WEIGHT), np.full(m_b, weights[0]),
                                          np.full(m_a, weights[1]))))
        gradient = np.zeros(size)
        gradient[:n] = -COMMAND_WEIGHT * previous
        rows = len(hard_rows) + 2 * m_b + 2 * m_a
        C = np.zeros((rows, size))
        low, high = np.full(rows, -np.inf), np.full(rows, np.inf)
        k = len(hard_rows)
        C[:k, :n] = program.C[hard_rows]
        low[:k], high[:k] = program.l[hard_rows], program.u[hard_rows]
        for j, row in enumerate(body_rows):
            C[k, :n] = C[k + 1, :n] = program.C[row]
            C[k, n + j], C[k + 1, n + j] = 1.0, -1.0
            low[k], high[k + 1] = program.l[row], program.u[row]
            k += 2
        lower = np.concatenate((hard_lower, np.zeros(m_b + m_a)))
        upper = np.concatenate((hard_upper, np.full(m_b + m_a, np.inf)))
        if acceleration_first:
            for j, column in enumerate(accelerated):
                C[k, column] = C[k + 1, column] = 1.0
                C[k, n + m_b + j], C[k + 1, n + m_b + j] = 1.0, -1.0
                low[k] = previous[column] - steps[column]
                high[k + 1] = previous[column] + steps[column]
                k += 2
        else:
            np.maximum(lower[:n], previous - steps, out=lower[:n])
            np.minimum(upper[:n], previous + steps, out=upper[:n])
        keep = np.isfinite(low) | np.isfinite(high)
        qp = QuadraticProgram(hessian, gradient, np.zeros((0, size)), np.zeros(0), C[keep],
                              low[keep], high[keep], lower, upper)
        solution = ProxqpSolver(eps_abs=RELAXATION_TOLERANCE, max_iter=self.max_iter).solve(qp)
        if not solution.found or not np.all(np.isfinite(solution.x)):
            return None
        x = solution.x
        if acceleration_first:
            slack = np.zeros(n)
            slack[accelerated] = np.maximum(x[n + m_b:], 0.0)
            return x[:n], slack
        return np.clip(x[:n], lower[:n], upper[:n]), np.maximum(x[n:], 0.0)

    @staticmethod
    def _apply(program, hard_lower, hard_upper, previous, limits, time_step, groups, joints,
               body_slack, acceleration_slack, steps) -> list[Relaxation]:
        """Widen the program's bounds by the slack found (``steps`` [rad/s or m/s]: the
        acceleration limits over a period, widened); the relaxations made."""
        relaxations = []
        j = 0
        for group in groups:
            if not group.relaxable:
                continue
            low, high = program.l[group.rows], program.u[group.rows]
            slack = body_slack[j:j + len(low)]
            j += len(low)
            widen = np.where(slack > MARGIN, slack + MARGIN, 0.0)
            low -= widen
            high += widen
            relaxed = np.flatnonzero(slack > MARGIN)
            if relaxed.size:
                relaxations.append(Relaxation(group.label, tuple(int(r) for r in relaxed),
                                              float(slack.max()), group.unit))
        np.maximum(hard_lower, previous - steps, out=program.lower)
        np.minimum(hard_upper, previous + steps, out=program.upper)
        relaxed = np.flatnonzero(acceleration_slack > MARGIN)
        excess = acceleration_slack / time_step
        for owner in sorted({limits.owners[i] for i in relaxed}):
            mine = [i for i in relaxed if limits.owners[i] == owner]
            relaxations.append(Relaxation(owner, tuple(joints[i] for i in mine),
                                          float(excess[mine].max()), "rad/s^2"))
        return relaxations


def _hold_what_is_broken(program, hard_lower, hard_upper, groups, joints) -> list[Relaxation]:
    """Let every promise the state already breaks stay as it is: zero velocity allowed
    for the joints and the rows that asked to be driven back."""
    relaxed = []
    back = (hard_lower > 0.0) | (hard_upper < 0.0)
    if back.any():
        np.minimum(hard_lower, 0.0, out=hard_lower)
        np.maximum(hard_upper, 0.0, out=hard_upper)
        relaxed.append(Relaxation("joint position limits",
                                  tuple(joints[i] for i in np.flatnonzero(back)), 0.0, "held"))
    for group in groups:
        if group.relaxable:
            continue
        low, high = program.l[group.rows], program.u[group.rows]
        pushing = (low > 0.0) | (high < 0.0)
        if pushing.any():
            amount = float(np.max(np.maximum(low, -high)[pushing]))
            np.minimum(low, 0.0, out=low)
            np.maximum(high, 0.0, out=high)
            relaxed.append(Relaxation(group.label, tuple(int(r) for r in np.flatnonzero(pushing)),
                                      amount, "held"))
    return relaxed
