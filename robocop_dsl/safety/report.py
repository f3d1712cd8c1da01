"""Reported: for each collision constraint, the smallest clearance over a run, and the
largest excess over each limit (zero when every promise held), from what the
controller measured every cycle, stops included."""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, field

import numpy as np

EXCESS_UNITS = {"position": "rad or m", "velocity": "rad/s or m/s",
                "acceleration": "rad/s^2 or m/s^2", "clearance": "m"}
TOLERANCE = {"position": 1e-6, "velocity": 1e-6, "acceleration": 1e-3, "clearance": 1e-3}
"""Excesses at or below these count as none: the solver's tolerance, a stop's last
command (below :data:`~robocop_dsl.safety.braking.AT_REST`, 1e-6 rad/s, zeroed in one
period of a millisecond: 1e-3 rad/s^2), and for clearances the 1 mm of slack of the
discrete step."""
_KINDS = np.arange(3)


@dataclass
class SafetyReport:
    """What a run kept of its promises.

    Attributes:
        clearances: Per collision constraint (label), the smallest distance measured
            between its shapes [m]; ``inf`` while no pair came within influence.
        min_distances: Per collision constraint, its ``min_distance`` [m] (the last set).
        excess: Per limit kind (:data:`EXCESS_UNITS`), the largest excess over it.
        excess_at: Per limit kind, what had the largest excess (a joint or a constraint).
        relaxed: Per constraint (label), the number of cycles it was relaxed in.
        budget_cycles: Cycles whose solver spent its iteration budget.
    """

    clearances: dict = field(default_factory=dict)
    min_distances: dict = field(default_factory=dict)
    excess: dict = field(default_factory=lambda: dict.fromkeys(EXCESS_UNITS, 0.0))
    excess_at: dict = field(default_factory=lambda: dict.fromkeys(EXCESS_UNITS, ""))
    relaxed: Counter = field(default_factory=Counter)
    budget_cycles: int = 0
    _rows: np.ndarray | None = field(default=None, repr=False, compare=False)

    def observe(self, controller, command: np.ndarray, previous: np.ndarray) -> None:
        """Take in one cycle of ``controller``: its state (the measured positions), the
        ``command`` sent and the ``previous`` one [rad/s or m/s]."""
        limits = controller.limits
        if limits is None:
            return
        state = controller.state
        positions = state.group_positions
        excess = self._excess_rows(len(positions))
        position, velocity, acceleration = excess
        np.maximum(np.subtract(limits.lower, positions, out=position),
                   np.subtract(positions, limits.upper, out=velocity), out=position)
        np.subtract(np.abs(command, out=velocity), limits.max_velocity, out=velocity)
        np.abs(np.subtract(command, previous, out=acceleration), out=acceleration)
        np.divide(acceleration, state.time_step, out=acceleration)
        np.subtract(acceleration, limits.max_acceleration, out=acceleration)
        if len(positions):
            worst = excess.argmax(axis=1)
            values = excess[_KINDS, worst].tolist()
            for kind, value, joint in zip(EXCESS_UNITS, values, worst.tolist()):
                if value > max(self.excess[kind], TOLERANCE[kind]):
                    self.excess[kind] = value
                    self.excess_at[kind] = state.group.joints[joint]
        for constraint in controller.constraints():
            if constraint.enabled and constraint.kind == "collision_avoidance":
                self._clearance(constraint)

    def _excess_rows(self, size: int) -> np.ndarray:
        """The work array of :meth:`observe`: one row per joint limit kind (position,
        velocity, acceleration), one column per joint."""
        rows = self._rows
        if rows is None or rows.shape[1] != size:
            rows = self._rows = np.zeros((3, size))
        return rows

    def count(self, result) -> None:
        """Count the relaxations and the spent budget of a
        :class:`~robocop_dsl.control.ControlResult`."""
        for name in {relaxation.constraint for relaxation in result.relaxations}:
            self.relaxed[name] += 1
        self.budget_cycles += result.status == "solver_budget"

    def _clearance(self, constraint) -> None:
        label = constraint.label
        self.min_distances[label] = constraint.min_distance
        distance = constraint.smallest_distance
        if distance < self.clearances.setdefault(label, math.inf):
            self.clearances[label] = distance
        excess = constraint.min_distance - distance
        if excess > max(self.excess["clearance"], TOLERANCE["clearance"]):
            self.excess["clearance"] = excess
            self.excess_at["clearance"] = label

    @property
    def held(self) -> bool:
        """Whether every promise held: no excess beyond :data:`TOLERANCE`."""
        return not any(self.excess.values())

    def as_event(self) -> dict:
        """The report as the ``end`` event's ``safety`` data (finite numbers or
        ``None`` for a clearance never measured)."""
        return {"clearance": {label: (value if math.isfinite(value) else None)
                              for label, value in self.clearances.items()},
                "excess": dict(self.excess),
                "excess_at": {kind: where for kind, where in self.excess_at.items() if where},
                "relaxed_cycles": dict(self.relaxed),
                "solver_budget_cycles": self.budget_cycles,
                "held": self.held}
