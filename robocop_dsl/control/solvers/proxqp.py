"""proxsuite's dense ProxQP, reused and warm-started while the problem size is fixed."""

from __future__ import annotations

import numpy as np

from .base import QPSolution, QPSolver, QuadraticProgram
from .portable import portable_proxsuite

proxsuite = portable_proxsuite()

_SOLVED = proxsuite.proxqp.QPSolverOutput.PROXQP_SOLVED
_WARM = proxsuite.proxqp.InitialGuess.WARM_START_WITH_PREVIOUS_RESULT
_COLD = proxsuite.proxqp.InitialGuess.NO_INITIAL_GUESS
_DENSE = proxsuite.proxqp.dense
_BACKEND = _DENSE.DenseBackend.PrimalDualLDLT
"""ProxQP's factorisation, fixed: the automatic choice switches to PrimalLDLT when there
are about twice as many inequality rows as variables, and PrimalLDLT takes thousands of
iterations (seconds) on a Hessian damped to 1e-6 along a singular direction."""


MAX_ITERATIONS = 100
"""ProxQP's iterations for a solve from a cold start (a few tens at most when the
program has a solution)."""
WARM_ITERATIONS = 30
"""ProxQP's iterations for a warm-started solve (a few while the program changes little
from one cycle to the next), retried cold when they do not suffice."""


class ProxqpSolver(QPSolver):
    """Keeps one ``proxsuite.proxqp.dense.QP``; rebuilds it only when sizes change.

    Solving the same :class:`QuadraticProgram` again (the controller rewrites its
    arrays every cycle) reuses the arguments prepared for it the first time.

    Args:
        eps_abs: Absolute tolerance on primal and dual residuals (1e-10: near a
            singularity, where the Hessian's smallest eigenvalue is the damping, the
            command is then within 1e-4 rad/s of DAQP's).
        max_iter: Iteration limit (reaching it is a failure): the solver's budget,
            which bounds a cycle's compute time.
        eps_infeasible: Threshold of ProxQP's primal and dual infeasibility
            certificates; ProxQP's default 1e-4 flags feasible problems of this scale
            as infeasible, and near-singular strictly convex ones (a damping of 1e-6
            along a singular direction) as unbounded.
        warm_start: Start from the previous solution. ProxQP's stopping test does not
            check complementarity, so a warm start from a solution that still meets a
            program whose only change is its bounds ends at once on that solution: a
            program whose cost never changes (the braking QP) is solved cold.
    """

    name = "proxqp"
    guarantees_tolerance = True

    def __init__(self, eps_abs: float = 1e-10, max_iter: int = MAX_ITERATIONS,
                 eps_infeasible: float = 1e-12, warm_start: bool = True):
        self.eps_abs = eps_abs
        self.warm_start = warm_start
        self.max_iter = max_iter
        self.eps_infeasible = eps_infeasible
        self._qp = None
        self._size: tuple[int, int, int] | None = None
        self._problem: QuadraticProgram | None = None
        self._problem_size = (0, 0, 0)
        self._arguments: tuple = ()

    def reset(self) -> None:
        self._qp = None
        self._size = None

    def solve(self, problem: QuadraticProgram) -> QPSolution:
        """Solve warm-started within :data:`WARM_ITERATIONS`; a warm failure is retried
        once from a cold start within ``max_iter`` (a warm start can make ProxQP report
        a feasible problem infeasible, or crawl)."""
        if problem is not self._problem:
            self._problem, self._problem_size = problem, problem.size
            self._arguments = _arguments(problem)
        size = self._problem_size
        warm = size == self._size
        solution = self._solve(size, warm)
        if not solution.found and warm:
            solution = self._solve(size, False)
        return solution

    def _solve(self, size: tuple[int, int, int], warm: bool) -> QPSolution:
        n, n_eq, n_in = size
        try:
            if warm:
                qp = self._qp
                qp.update(*self._arguments)
                qp.solve()
            else:
                qp = _DENSE.QP(n, n_eq, n_in, True, _DENSE.HessianType.Dense, _BACKEND)
                settings = qp.settings
                settings.eps_abs = self.eps_abs
                settings.eps_rel = 0.0
                settings.max_iter = self.max_iter
                settings.eps_primal_inf = self.eps_infeasible
                settings.eps_dual_inf = self.eps_infeasible
                qp.init(*self._arguments)
                self._qp, self._size = qp, size
                qp.solve()
                settings.initial_guess = _WARM if self.warm_start else _COLD
                settings.max_iter = min(WARM_ITERATIONS, self.max_iter)
        except (RuntimeError, ValueError) as error:
            self.reset()
            return QPSolution(False, np.zeros(n), status=f"error: {error}")
        results = qp.results
        info = results.info
        if info.status == _SOLVED:
            return QPSolution(True, results.x.copy(), info.iter, "solved")
        self.reset()
        return QPSolution(False, np.zeros(n), info.iter, info.status.name)


def _arguments(problem: QuadraticProgram) -> tuple:
    """``problem`` as the arguments of ``QP.init`` / ``QP.update`` (``None`` for the
    empty equality and inequality blocks)."""
    _, n_eq, n_in = problem.size
    return (problem.H, problem.g, problem.A if n_eq else None, problem.b if n_eq else None,
            problem.C if n_in else None, problem.l if n_in else None,
            problem.u if n_in else None, problem.lower, problem.upper)
