"""QP backends: proxsuite's ProxQP (reused, warm-started) and any qpsolvers backend."""

from __future__ import annotations

import qpsolvers

from ..exceptions import UnknownSolver
from .base import QPSolution, QPSolver, QuadraticProgram
from .proxqp import ProxqpSolver
from .qpsolvers_backend import QpsolversSolver


def available_solvers() -> list[str]:
    """Names of the installed backends."""
    return sorted(set(qpsolvers.available_solvers))


def make_solver(name: str) -> QPSolver:
    """A solver instance for ``name``; ``"proxqp"`` uses the warm-started fast path.

    Raises:
        UnknownSolver: ``name`` is not an installed qpsolvers backend.
    """
    installed = available_solvers()
    if name not in installed:
        raise UnknownSolver(name, installed)
    if name == "proxqp":
        return ProxqpSolver()
    return QpsolversSolver(name)


__all__ = ["ProxqpSolver", "QPSolution", "QPSolver", "QpsolversSolver", "QuadraticProgram",
           "available_solvers", "make_solver"]
