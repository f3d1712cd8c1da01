"""The safety layer's part of a run: what the loop asks of it every cycle."""

from __future__ import annotations

import numpy as np

from .braking import stop_cycles
from .report import SafetyReport


class RunGuard:
    """Announces what the controller relaxed or answered with the braking QP, brakes
    once the run has ended, and keeps the run's :class:`SafetyReport`.

    Args:
        controller: The run's :class:`~robocop_dsl.control.Controller`.
        notify: ``notify(kind, data)`` raises an event of the run.
    """

    def __init__(self, controller, notify):
        self.controller = controller
        self.notify = notify
        self.report = SafetyReport()
        self.stopping_cycles = 0
        """Cycles of the stop so far."""
        self._stop_cycles: int | None = None

    def announce(self, result, state: str) -> None:
        """Count and announce the relaxations and the spent budget of a cycle's
        :class:`~robocop_dsl.control.ControlResult` in the active configuration
        ``state``."""
        if result.solved:
            return
        self.report.count(result)
        if result.status == "solver_budget":
            self.notify("solver_budget", {
                "message": "the QP solver found no answer within its iteration budget: "
                           "braking QP's command",
                "state": state})
        for relaxation in result.relaxations:
            self.notify("constraint_relaxed", {**relaxation.as_event(), "state": state})

    def brake(self, q: np.ndarray, last_command: np.ndarray, state: str,
              hold: bool = False) -> np.ndarray:
        """The command [rad/s or m/s] of one cycle of the stop at ``q`` (nq): the braking
        QP's, until at rest; zero when ``hold`` (no robot to brake) or once the stop has
        taken :func:`~robocop_dsl.safety.braking.stop_cycles` from ``last_command``.
        Raises what the controller's ``brake`` raises."""
        controller = self.controller
        if self._stop_cycles is None:
            self._stop_cycles = stop_cycles(controller.limits, last_command,
                                            controller.time_step)
        self.stopping_cycles += 1
        if hold or self.stopping_cycles > self._stop_cycles:
            return np.zeros(controller.state.dofs)
        result = controller.brake(q, previous=last_command)
        self.announce(result, state)
        return result.velocity

    def observe(self, command: np.ndarray, previous: np.ndarray) -> None:
        """Take in the cycle's ``command`` and the ``previous`` one [rad/s or m/s]."""
        self.report.observe(self.controller, command, previous)
