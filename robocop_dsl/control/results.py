"""What one controller cycle returns."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(slots=True)
class LevelResult:
    """One priority level of a cycle (treat as read-only).

    Attributes:
        priority: The level's priority (0 the highest; 0 for the weighted QP).
        tasks: Names of the level's tasks.
        solved: Whether the level's QP was solved (a lower level that fails keeps the
            command of the levels above).
        status: The solver's status.
        objectives: The level's task objectives (``Objective``) of the cycle.
        command: The final command of the cycle.
    """

    priority: int
    tasks: tuple[str, ...]
    solved: bool
    status: str = ""
    objectives: tuple = field(default=(), repr=False, compare=False)
    command: np.ndarray | None = field(default=None, repr=False, compare=False)

    @property
    def residual(self) -> float:
        """``sqrt(sum w (J dq - v)^2)`` over the level's tasks at the final command
        [task units/s] (computed on access)."""
        total = 0.0
        for objective in self.objectives:
            error = objective.jacobian @ self.command - objective.velocity
            total += float(error @ (objective.weight * error))
        return float(np.sqrt(total))


@dataclass(slots=True)
class Timings:
    """Durations of the parts of a cycle [s] (treat as read-only)."""

    kinematics: float = 0.0
    tasks: float = 0.0
    constraints: float = 0.0
    solve: float = 0.0
    total: float = 0.0


class ControlResult:
    """The command of one cycle (treat as read-only).

    Attributes:
        velocity: Joint-velocity command of the controlled group [rad/s or m/s], in the
            group's joint order, never NaN; zeros when no command was found.
        solved: Whether the hierarchy's command satisfies every enabled constraint.
        levels: Per priority level results, highest priority first (built on first
            access when the controller passes a function that builds them).
        timings: Where the time went.
        reason: Why no command was found (``status == "no_solution"``), else ``None``.
        relaxations: The constraints relaxed this cycle
            (:class:`~robocop_dsl.safety.Relaxation`).
        status: ``solved``, ``relaxed`` (a command under relaxed constraints),
            ``solver_budget`` (the braking QP's command: the solver found none within its
            iteration budget) or ``no_solution`` (non-finite input, or position limits
            that leave a joint no position: a zero command).
    """

    __slots__ = ("velocity", "solved", "_levels", "timings", "reason", "relaxations",
                 "status")

    def __init__(self, velocity: np.ndarray, solved: bool, levels=(),
                 timings: Timings | None = None, reason: str | None = None,
                 relaxations: tuple = (), status: str = "solved"):
        self.velocity = velocity
        self.solved = solved
        self._levels = levels
        self.timings = Timings() if timings is None else timings
        self.reason = reason
        self.relaxations = relaxations
        self.status = status

    @property
    def levels(self) -> tuple[LevelResult, ...]:
        """Per priority level results, highest priority first."""
        levels = self._levels
        if callable(levels):
            levels = self._levels = levels()
        return levels

    @property
    def failed(self) -> bool:
        """Whether the cycle failed (relaxed, budget spent or no command)."""
        return not self.solved

    @property
    def residuals(self) -> tuple[float, ...]:
        """Residual of each level, highest priority first."""
        return tuple(level.residual for level in self.levels)

    def __repr__(self) -> str:
        state = "solved" if self.solved else f"failed: {self.reason}"
        residuals = ", ".join(f"{r:.3g}" for r in self.residuals)
        return (f"ControlResult({state}, |velocity|={np.linalg.norm(self.velocity):.4g}, "
                f"residuals=[{residuals}], total={self.timings.total * 1e6:.0f} us)")
