"""proxsuite's dense ProxQP, reused and warm-started while the problem size is fixed."""

from __future__ import annotations

import numpy as np
import proxsuite

from .base import QPSolution, QPSolver, QuadraticProgram

_SOLVED = proxsuite.proxqp.QPSolverOutput.PROXQP_SOLVED
_WARM = proxsuite.proxqp.InitialGuess.WARM_START_WITH_PREVIOUS_RESULT


class ProxqpSolver(QPSolver):
    """Keeps one ``proxsuite.proxqp.dense.QP``; rebuilds it only when sizes change.

    Args:
        eps_abs: Absolute tolerance on primal and dual residuals.
        max_iter: Iteration limit (reaching it is a failure).
    """

    name = "proxqp"

    def __init__(self, eps_abs: float = 1e-9, max_iter: int = 1000):
        self.eps_abs = eps_abs
        self.max_iter = max_iter
        self._qp = None
        self._size: tuple[int, int, int] | None = None

    def reset(self) -> None:
        self._qp = None
        self._size = None

    def solve(self, problem: QuadraticProgram) -> QPSolution:
        n, n_eq, n_in = size = problem.size
        args = (problem.H, problem.g, problem.A if n_eq else None, problem.b if n_eq else None,
                problem.C if n_in else None, problem.l if n_in else None,
                problem.u if n_in else None, problem.lower, problem.upper)
        try:
            if size != self._size:
                qp = proxsuite.proxqp.dense.QP(n, n_eq, n_in, True)
                qp.settings.eps_abs = self.eps_abs
                qp.settings.eps_rel = 0.0
                qp.settings.max_iter = self.max_iter
                qp.settings.initial_guess = _WARM
                qp.init(*args)
                self._qp, self._size = qp, size
            else:
                qp = self._qp
                qp.update(*args)
            qp.solve()
        except (RuntimeError, ValueError) as error:
            self.reset()
            return QPSolution(False, np.zeros(n), status=f"error: {error}")
        info = qp.results.info
        found = info.status == _SOLVED
        if not found:
            self.reset()
        return QPSolution(found, qp.results.x.copy() if found else np.zeros(n), info.iter,
                          info.status.name)
