"""QP backends: DAQP called directly and proxsuite's ProxQP (both reused and
warm-started), any qpsolvers backend, and ``auto``: one of the first two per QP
(:mod:`.choice`).

qpsolvers (and SciPy with it) is imported only when another backend is named or the
installed ones are listed: DAQP and ProxQP need neither, and `check` stays quick.
ProxQP is imported first, in its portable build (:mod:`.portable`), before qpsolvers
can import another.
"""

from __future__ import annotations

from ..exceptions import UnknownSolver
from .base import QPSolution, QPSolver, QuadraticProgram
from .choice import AUTO, level_backends
from .proxqp import ProxqpSolver

DIRECT = (AUTO, "daqp", ProxqpSolver.name)
"""The names served without qpsolvers."""


def available_solvers() -> list[str]:
    """Names a ``solver`` option accepts: ``auto``, ``daqp``, ``proxqp`` and the
    installed qpsolvers backends."""
    import qpsolvers

    return sorted(set(qpsolvers.available_solvers) | set(DIRECT))


def make_solver(name: str, warm_start: bool = True) -> QPSolver:
    """A solver instance for ``name``: ``"daqp"`` and ``"proxqp"`` are called directly
    and warm-started unless ``warm_start`` is false (see :class:`ProxqpSolver` and
    :class:`~.daqp_direct.DaqpSolver`); ``"auto"`` is the rule's choice for a QP
    without equality rows (:func:`level_solvers` applies it to a hierarchy).

    Raises:
        UnknownSolver: ``name`` is not an installed qpsolvers backend.
    """
    if name == ProxqpSolver.name:
        return ProxqpSolver(warm_start=warm_start)
    if name in (AUTO, "daqp"):
        from .daqp_direct import DaqpSolver

        return DaqpSolver(warm_start=warm_start)
    installed = available_solvers()
    if name not in installed:
        raise UnknownSolver(name, installed)
    from .qpsolvers_backend import QpsolversSolver

    return QpsolversSolver(name)


def level_solvers(name: str, dimensions: list[list[int]], dofs: int) -> list[QPSolver]:
    """One solver per level of a hierarchy: ``name``'s, or for ``"auto"`` the rule's
    (:func:`~.choice.level_backends`).

    Args:
        name: The controller's solver.
        dimensions: The rows of every task of each level, highest priority first.
        dofs: Size of the command.
    """
    names = level_backends(dimensions, dofs) if name == AUTO else [name] * len(dimensions)
    return [make_solver(backend) for backend in names]


def braking_solver(name: str) -> QPSolver:
    """The braking QP's solver: for ``"auto"`` DAQP, warm-started (its stopping test
    checks every optimality condition, so a warm start is exact); for a named solver,
    that one without warm start (ProxQP's warm start can stop on a stale answer when
    only the bounds change)."""
    return make_solver("daqp") if name == AUTO else make_solver(name, warm_start=False)


__all__ = ["AUTO", "ProxqpSolver", "QPSolution", "QPSolver", "QuadraticProgram",
           "available_solvers", "braking_solver", "level_solvers", "make_solver"]
