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

import math

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .results import LevelResult
from .solvers import QPSolver, QuadraticProgram

FEASIBILITY_TOLERANCE = 1e-6
"""Largest constraint violation [command units] accepted from a solver."""


class Objective(NamedTuple):
    """A task's contribution this cycle: minimise ``sum w (J dq - v)^2``."""

    name: str
    jacobian: np.ndarray
    velocity: np.ndarray
    weight: np.ndarray


@dataclass(slots=True)
class Bounds:
    """The enabled constraints: box bounds and rows ``l <= C dq <= u``."""

    lower: np.ndarray
    upper: np.ndarray
    C: np.ndarray
    l: np.ndarray
    u: np.ndarray


def level_problem(objectives: list[Objective], bounds: Bounds, regularisation: np.ndarray,
                  equalities: tuple[np.ndarray, np.ndarray]) -> QuadraticProgram:
    """The QP of one level: weighted task residuals plus ``dq' regularisation dq``."""
    A, b = equalities
    if not objectives:
        return QuadraticProgram(regularisation, np.zeros(regularisation.shape[0]), A, b,
                                bounds.C, bounds.l, bounds.u, bounds.lower, bounds.upper)
    if len(objectives) == 1:
        _, jacobian, velocity, weight = objectives[0]
    else:
        jacobian = np.vstack([objective.jacobian for objective in objectives])
        velocity = np.concatenate([objective.velocity for objective in objectives])
        weight = np.concatenate([objective.weight for objective in objectives])
    weighted = jacobian.T * weight
    return QuadraticProgram(weighted @ jacobian + regularisation, -(weighted @ velocity), A, b,
                            bounds.C, bounds.l, bounds.u, bounds.lower, bounds.upper)


def solve_levels(levels: list[tuple[int, list[Objective]]], bounds: Bounds,
                 solvers: list[QPSolver], regularisation: np.ndarray):
    """Solve the levels in order.

    A level with no task minimises ``|dq|^2`` alone (the smallest feasible command);
    the others add ``dq' regularisation dq`` to their tasks' residual. Solutions of
    backends that do not guarantee their tolerance are checked against the
    constraints (:data:`FEASIBILITY_TOLERANCE`).

    Returns:
        ``(command, level_results, problems)``; ``command`` is ``None`` when the first
        level has no solution.
    """
    n = bounds.lower.shape[0]
    command = None
    statuses: list[tuple[bool, str]] = []
    problems: list[QuadraticProgram] = []
    kept_rows: list[np.ndarray] = []
    equalities = (np.zeros((0, n)), np.zeros(0))
    for (priority, objectives), solver in zip(levels, solvers):
        if kept_rows:
            A = np.vstack(kept_rows)
            equalities = (A, A @ command)
        problem = level_problem(objectives, bounds,
                                regularisation if objectives else np.eye(n), equalities)
        problems.append(problem)
        solution = solver.solve(problem)
        solved = solution.found and math.isfinite(solution.x @ solution.x)
        if solved and not solver.guarantees_tolerance:
            solved = problem.violation(solution.x) <= FEASIBILITY_TOLERANCE
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
        results.append(LevelResult(priority, tuple([o.name for o in objectives]), solved,
                                   status, tuple(objectives), command))
    return command, tuple(results), problems
