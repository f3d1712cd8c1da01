"""Priority handling: one weighted QP, or one QP per level (strict hierarchy).

Strict hierarchy: levels are solved from the highest priority (0) down. Level ``k``
minimises its tasks' weighted residual plus a damping, subject to the enabled
constraints and to equality constraints ``J_j dq = J_j dq*`` on the task velocities
``J_j dq*`` achieved by every task ``j`` of the levels above (``dq*`` the solution
of level ``k - 1``). A lower level can therefore only use the freedom left by the
levels above and never changes their achieved task velocities. If a lower level has
no solution, the command of the level above is kept.

The damping of a level is ``(damping + lm_damping * sum w |e|^2) |dq|^2``: a constant
that keeps the QP strictly convex, and a Levenberg-Marquardt term that grows with the
weighted squared tracking errors ``e`` of the level's position-like tasks (from where
they are to their references; Pink's and mink's ``lm_damping``; velocity tasks do not
count). On a trajectory and near a target it vanishes; toward a target out of reach,
where the error stays, it damps the motion along the singular directions that would
otherwise flip sign every cycle.

The QPs are assembled in place: a :class:`Hierarchy` owns, for one set of enabled
tasks and constraints, the stacked task rows (level by level, so the equality rows
of level ``k`` are the rows of the levels above it, without copying), the constraint
rows and bounds, and one :class:`QuadraticProgram` per level over those buffers.
"""

from __future__ import annotations

import math
from functools import partial
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


class _Level(NamedTuple):
    """One level's views of the stacked rows, its buffers, QP and solver."""

    priority: int
    tasks: list[int]
    names: tuple[str, ...]
    jacobian: np.ndarray
    velocity: np.ndarray
    weight: np.ndarray
    weighted_rows: np.ndarray
    weighted: np.ndarray
    diagonal: np.ndarray
    """A view of the diagonal of the level's Hessian."""
    program: QuadraticProgram
    solver: QPSolver


class Hierarchy:
    """The QPs of the priority levels, with buffers reused from cycle to cycle.

    Each cycle the controller writes the task rows (:meth:`task_rows`) into
    :attr:`jacobian`, :attr:`velocity` and :attr:`weight`, the box bounds into
    :attr:`lower` / :attr:`upper` and the constraint rows into :attr:`C`, :attr:`l`
    and :attr:`u`, then calls :meth:`solve`.

    Args:
        levels: ``(priority, task indices)`` per level, highest priority first; only
            a single level may have no task (it then minimises ``|dq|^2`` alone).
        names: The name of every task, by index.
        dimensions: The number of rows of every task, by index.
        dofs: Size of the command.
        constraint_rows: Number of constraint rows ``l <= C dq <= u``.
        solvers: One solver per level.
        damping: Weight of ``|dq|^2`` added to the levels with tasks [-].
        lm_damping: Weight of ``|dq|^2`` per unit of the level's weighted squared
            tracking error ``sum w |e|^2`` [per task unit^2].
    """

    def __init__(self, levels: list[tuple[int, list[int]]], names: list[str],
                 dimensions: list[int], dofs: int, constraint_rows: int,
                 solvers: list[QPSolver], damping: float, lm_damping: float = 0.0):
        total = sum(dimensions)
        self.jacobian = np.zeros((total, dofs))
        self.velocity = np.zeros(total)
        self.weight = np.zeros((total, dofs))
        """Each task row's weight, repeated along the row (multiplying two arrays of
        one shape is cheaper than broadcasting a column)."""
        self.lower = np.full(dofs, -np.inf)
        self.upper = np.full(dofs, np.inf)
        self.C = np.zeros((constraint_rows, dofs))
        self.l = np.zeros(constraint_rows)
        self.u = np.zeros(constraint_rows)
        self._rows: list[slice] = [slice(0)] * len(dimensions)
        self._levels: list[_Level] = []
        start = 0
        for (priority, tasks), solver in zip(levels, solvers):
            end = start
            for index in tasks:
                self._rows[index] = slice(end, end + dimensions[index])
                end += dimensions[index]
            hessian = np.zeros((dofs, dofs)) if tasks else np.eye(dofs)
            program = QuadraticProgram(hessian, np.zeros(dofs), self.jacobian[:start],
                                       np.zeros(start), self.C, self.l, self.u, self.lower,
                                       self.upper)
            weighted_rows = np.zeros((end - start, dofs))
            self._levels.append(_Level(
                priority, list(tasks), tuple(names[index] for index in tasks),
                self.jacobian[start:end], self.velocity[start:end],
                self.weight[start:end], weighted_rows, weighted_rows.T,
                hessian.reshape(-1)[::dofs + 1], program, solver))
            start = end
        self.squared_errors = [0.0] * len(dimensions)
        """Each task's weighted squared tracking error ``w |e|^2``, by index, written by
        the controller every cycle (0 for velocity tasks)."""
        self._damping = damping
        self._lm_damping = lm_damping
        self.problems = [level.program for level in self._levels]
        """The QP of each level, overwritten by every cycle."""
        self._not_run = [(False, "not run")] * len(self._levels)

    def task_rows(self, index: int) -> slice:
        """The rows of task ``index`` in :attr:`jacobian`, :attr:`velocity`, :attr:`weight`."""
        return self._rows[index]

    def solve(self, objectives: list[Objective]):
        """Solve the levels in order.

        A level with no task minimises ``|dq|^2`` alone (the smallest feasible
        command); the others add their damping (see the module) to their tasks'
        residual.
        Solutions of backends that do not guarantee their tolerance are checked
        against the constraints (:data:`FEASIBILITY_TOLERANCE`).

        Args:
            objectives: The objective of every task, by index (the results keep them).

        Returns:
            ``(command, level_results, problems)``: ``problems`` are the QPs that were
            solved; ``command`` is ``None`` when the first level has no solution;
            ``level_results`` builds the :class:`LevelResult` of every level when
            called (``()`` without a command).
        """
        command = None
        statuses: list[tuple[bool, str]] = []
        squared_errors, lm_damping = self.squared_errors, self._lm_damping
        for level in self._levels:
            program = level.program
            if level.tasks:
                weighted, diagonal = level.weighted, level.diagonal
                np.multiply(level.jacobian, level.weight, out=level.weighted_rows)
                weighted.dot(level.jacobian, out=program.H)
                damping = self._damping
                if lm_damping:
                    damping += lm_damping * sum([squared_errors[index]
                                                 for index in level.tasks])
                np.add(diagonal, damping, out=diagonal)
                weighted.dot(level.velocity, out=program.g)
                np.negative(program.g, out=program.g)
            if command is not None:
                program.A.dot(command, out=program.b)
            solver = level.solver
            solution = solver.solve(program)
            x = solution.x
            solved = solution.found and math.isfinite(x.dot(x))
            if solved and not solver.guarantees_tolerance:
                solved = program.violation(x) <= FEASIBILITY_TOLERANCE
            statuses.append((solved, solution.status))
            if not solved:
                break
            command = x
        count = len(statuses)
        problems = self.problems[:count]
        if command is None:
            return None, (), problems
        return command, partial(self._results, statuses, objectives, command), problems

    def _results(self, statuses: list[tuple[bool, str]], objectives: list[Objective],
                 command: np.ndarray) -> tuple[LevelResult, ...]:
        """The :class:`LevelResult` of every level, from the ``(solved, status)`` of
        those that ran."""
        statuses = statuses + self._not_run[len(statuses):]
        return tuple([LevelResult(level.priority, level.names, solved, status,
                                  tuple([objectives[index] for index in level.tasks]),
                                  command)
                      for level, (solved, status) in zip(self._levels, statuses)])
