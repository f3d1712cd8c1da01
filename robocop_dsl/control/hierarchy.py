"""Priority handling: one weighted QP, or one QP per level (strict hierarchy).

Strict hierarchy: levels are solved from the highest priority (0) down. Level ``k``
minimises its tasks' weighted residual plus a small damping, subject to the enabled
constraints and to equality constraints ``J_j dq = J_j dq*`` on the task velocities
``J_j dq*`` achieved by every task ``j`` of the levels above (``dq*`` the solution
of level ``k - 1``). A lower level can therefore only use the freedom left by the
levels above and never changes their achieved task velocities. If a lower level has
no solution, the command of the level above is kept.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .results import LevelResult
from .solvers import QPSolver, QuadraticProgram

FEASIBILITY_TOLERANCE = 1e-6
"""Largest constraint violation [command units] accepted from a solver."""


@dataclass
class Objective:
    """A task's contribution this cycle: minimise ``sum w (J dq - v)^2``."""

    name: str
    jacobian: np.ndarray
    velocity: np.ndarray
    weight: np.ndarray


@dataclass
class Bounds:
    """The enabled constraints: box bounds and rows ``l <= C dq <= u``."""

    lower: np.ndarray
    upper: np.ndarray
    C: np.ndarray
    l: np.ndarray
    u: np.ndarray


def level_problem(objectives: list[Objective], bounds: Bounds, damping: float,
                  equalities: tuple[np.ndarray, np.ndarray]) -> QuadraticProgram:
    """The QP of one level: weighted task residuals plus ``damping |dq|^2``."""
    n = bounds.lower.shape[0]
    H = np.eye(n) * (damping if objectives else 1.0)
    g = np.zeros(n)
    for objective in objectives:
        weighted = objective.jacobian.T * objective.weight
        H += weighted @ objective.jacobian
        g -= weighted @ objective.velocity
    A, b = equalities
    return QuadraticProgram(H, g, A, b, bounds.C, bounds.l, bounds.u, bounds.lower,
                            bounds.upper)


def residual(objectives: list[Objective], command: np.ndarray) -> float:
    """Weighted residual norm of ``objectives`` at ``command``."""
    total = 0.0
    for objective in objectives:
        error = objective.jacobian @ command - objective.velocity
        total += float(error @ (objective.weight * error))
    return float(np.sqrt(total))


def solve_levels(levels: list[tuple[int, list[Objective]]], bounds: Bounds,
                 solvers: list[QPSolver], damping: float):
    """Solve the levels in order.

    Returns:
        ``(command, level_results, problems)``; ``command`` is ``None`` when the first
        level has no solution.
    """
    n = bounds.lower.shape[0]
    command = None
    statuses: list[tuple[bool, str]] = []
    problems: list[QuadraticProgram] = []
    kept_rows: list[np.ndarray] = []
    for (priority, objectives), solver in zip(levels, solvers):
        if kept_rows:
            A = np.vstack(kept_rows)
            equalities = (A, A @ command)
        else:
            equalities = (np.zeros((0, n)), np.zeros(0))
        problem = level_problem(objectives, bounds, damping, equalities)
        problems.append(problem)
        solution = solver.solve(problem)
        solved = (solution.found and bool(np.isfinite(solution.x).all())
                  and problem.violation(solution.x) <= FEASIBILITY_TOLERANCE)
        statuses.append((solved, solution.status))
        if not solved:
            break
        command = solution.x
        kept_rows.extend(objective.jacobian for objective in objectives)
    if command is None:
        return None, (), problems
    results = []
    for index, (priority, objectives) in enumerate(levels):
        solved, status = statuses[index] if index < len(statuses) else (False, "not run")
        results.append(LevelResult(priority, tuple(o.name for o in objectives), solved,
                                   residual(objectives, command), status))
    return command, tuple(results), problems
