"""QP backends: proxsuite's ProxQP (reused, warm-started) and any qpsolvers backend.

qpsolvers (and SciPy with it) is imported only when another backend is named or the
installed ones are listed: ProxQP needs neither, and `check` stays quick. ProxQP is
imported first, in its portable build (:mod:`.portable`), before qpsolvers can import
another.
"""

from __future__ import annotations

from ..exceptions import UnknownSolver
from .base import QPSolution, QPSolver, QuadraticProgram
from .proxqp import ProxqpSolver


def available_solvers() -> list[str]:
    """Names of the installed backends (``proxqp`` always)."""
    import qpsolvers

    return sorted(set(qpsolvers.available_solvers) | {ProxqpSolver.name})


def make_solver(name: str, warm_start: bool = True) -> QPSolver:
    """A solver instance for ``name``; ``"proxqp"`` uses the fast path, warm-started
    unless ``warm_start`` is false (see :class:`ProxqpSolver`).

    Raises:
        UnknownSolver: ``name`` is not an installed qpsolvers backend.
    """
    if name == ProxqpSolver.name:
        return ProxqpSolver(warm_start=warm_start)
    installed = available_solvers()
    if name not in installed:
        raise UnknownSolver(name, installed)
    from .qpsolvers_backend import QpsolversSolver

    return QpsolversSolver(name)


__all__ = ["ProxqpSolver", "QPSolution", "QPSolver", "QuadraticProgram", "available_solvers",
           "make_solver"]
