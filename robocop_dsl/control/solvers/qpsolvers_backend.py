"""Any installed qpsolvers backend, through ``qpsolvers.solve_problem``."""

from __future__ import annotations

import numpy as np
import qpsolvers

from .base import QPSolution, QPSolver, QuadraticProgram


class QpsolversSolver(QPSolver):
    """Solves each cycle from scratch with a qpsolvers backend.

    Two-sided rows ``l <= Cx <= u`` are passed as ``Gx <= h`` without infinite rows.

    Args:
        name: A name in ``qpsolvers.available_solvers``.
        **options: Passed to the backend.
    """

    def __init__(self, name: str, **options):
        self.name = name
        self.options = options

    def solve(self, problem: QuadraticProgram) -> QPSolution:
        n = problem.validate().size[0]
        upper_rows = np.isfinite(problem.u)
        lower_rows = np.isfinite(problem.l)
        G = np.vstack((problem.C[upper_rows], -problem.C[lower_rows]))
        h = np.concatenate((problem.u[upper_rows], -problem.l[lower_rows]))
        qp = qpsolvers.Problem(
            problem.H, problem.g, G if h.size else None, h if h.size else None,
            problem.A if problem.b.size else None, problem.b if problem.b.size else None,
            problem.lower, problem.upper)
        try:
            solution = qpsolvers.solve_problem(qp, solver=self.name, **self.options)
        except (qpsolvers.QPError, ValueError, ArithmeticError) as error:
            return QPSolution(False, np.zeros(n), status=f"error: {error}")
        found = bool(solution.found) and solution.x is not None
        x = np.asarray(solution.x, dtype=float) if found else np.zeros(n)
        return QPSolution(found, x, status="found" if found else "not found")
