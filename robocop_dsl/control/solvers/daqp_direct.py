"""DAQP's dual active-set solver, called directly: one workspace kept between cycles,
warm-started from the working set of the cycle before."""

from __future__ import annotations

import math

import daqp
import numpy as np

from .base import QPSolution, QPSolver, QuadraticProgram

INFINITY = 1e30
"""DAQP's infinite bound: larger bounds are clipped to it."""
EQUALITY = 5
"""DAQP's sense of an equality row (active and immutable)."""
MAX_ITERATIONS = 1000
"""DAQP's iterations per solve (one constraint added to or removed from the working set
each; a cold start on the controller's programs takes about as many as there are
binding rows, a warm start a few): the solver's budget, which bounds a cycle's compute
time."""
STATUS = {2: "soft_optimal", 1: "solved", -1: "infeasible", -2: "cycling", -3: "unbounded",
          -4: "iteration_limit", -5: "nonconvex", -6: "overdetermined_initial",
          -7: "time_limit", -8: "unsupported"}
"""DAQP's exit flags, as text."""
_RETRY_COLD = (-2, -4)
"""Failures a warm start may cause (cycling, iteration limit): retried once cold."""


class DaqpSolver(QPSolver):
    """Keeps one ``daqp.Model`` for the :class:`QuadraticProgram` it solves (the
    controller rewrites the same program every cycle); the stacked arrays DAQP takes
    are allocated when a program is first seen, then rewritten in place.

    DAQP's rows are the ``n`` bounds first, then the general rows: ``l <= Cx <= u``,
    then ``Ax = b`` as rows whose lower and upper bounds are both ``b``, flagged as
    equalities. ``daqp.Model.update`` keeps the working set of the last solve when the
    sense flags are not passed, so a cycle starts from the rows that bound the command
    the cycle before (a warm start: a few iterations while the binding rows do not
    change). DAQP is an active-set method: its stopping test checks every optimality
    condition, so a warm start never ends early on a stale answer (unlike ProxQP's,
    :class:`~.proxqp.ProxqpSolver`), and a reported solution meets every inactive row
    to ``primal_tol`` in the program's own units and every active one exactly (up to
    rounding).

    Args:
        warm_start: Start each solve from the last working set; when false, each
            solve starts from the equality rows alone.
        primal_tol: Largest violation of a row DAQP accepts [command units].
        max_iter: Iteration limit (reaching it is a failure).
    """

    name = "daqp"
    guarantees_tolerance = True

    def __init__(self, warm_start: bool = True, primal_tol: float = 1e-9,
                 max_iter: int = MAX_ITERATIONS):
        self.warm_start = warm_start
        self.settings = {"primal_tol": primal_tol, "iter_limit": max_iter}
        self._model: daqp.Model | None = None
        self._problem: QuadraticProgram | None = None
        self._n = 0
        self._copies: tuple = ()
        self._arrays: dict = {}
        self._rows = np.zeros((0, 0))
        self._sense = np.zeros(0, dtype=np.intc)
        self._cold = True

    def reset(self) -> None:
        self._model = None

    def solve(self, problem: QuadraticProgram) -> QPSolution:
        """Solve from the last working set; a warm solve that cycles or runs out of
        iterations is retried once from the equality rows alone."""
        if problem is not self._problem:
            self._prepare(problem)
        for source, target in self._copies:
            np.copyto(target, source)
        arrays = self._arrays
        np.maximum(arrays["blower"], -INFINITY, out=arrays["blower"])
        np.minimum(arrays["bupper"], INFINITY, out=arrays["bupper"])
        model = self._model
        if model is None:
            model = daqp.Model()
            model.settings = self.settings
            flag = model.setup(arrays["H"], arrays["f"], self._rows, arrays["bupper"],
                               arrays["blower"], self._sense)[0]
        elif self._cold or not self.warm_start:
            flag = model.update(sense=self._sense, **arrays)
        else:
            flag = model.update(**arrays)
        if flag < 0:
            self._model = None
            return QPSolution(False, np.zeros(self._n), status=STATUS.get(flag, str(flag)))
        self._model = model
        x, _, flag, info = model.solve()
        iterations = info["iterations"]
        if flag in _RETRY_COLD and not self._cold and model.update(sense=self._sense) >= 0:
            x, _, flag, info = model.solve()
            iterations += info["iterations"]
        solved = flag == 1 and math.isfinite(x.dot(x))
        self._cold = not solved
        if solved:
            return QPSolution(True, x, iterations, "solved")
        status = STATUS.get(flag, str(flag)) if flag != 1 else "not finite"
        return QPSolution(False, np.zeros(self._n), iterations, status)

    def _prepare(self, problem: QuadraticProgram) -> None:
        """Allocate DAQP's stacked arrays for ``problem`` and list the copies that fill
        them each cycle (an array DAQP can read in place, such as ``H``, is not
        copied)."""
        n, n_eq, n_in = problem.validate().size
        m = n + n_in + n_eq
        lower, upper = np.empty(m), np.empty(m)
        copies = [(problem.lower, lower[:n]), (problem.upper, upper[:n]),
                  (problem.l, lower[n:n + n_in]), (problem.u, upper[n:n + n_in]),
                  (problem.b, lower[n + n_in:]), (problem.b, upper[n + n_in:])]
        if n_eq and n_in:
            rows = np.empty((n_in + n_eq, n))
            copies += [(problem.C, rows[:n_in]), (problem.A, rows[n_in:])]
        else:
            rows = _in_place(problem.A if n_eq else problem.C, copies)
        self._arrays = {"H": _in_place(problem.H, copies), "f": _in_place(problem.g, copies),
                        "bupper": upper, "blower": lower}
        self._copies = tuple((source, target) for source, target in copies if source.size)
        if n_eq + n_in:
            self._arrays["A"] = rows
        self._rows = rows
        self._sense = np.zeros(m, dtype=np.intc)
        self._sense[n + n_in:] = EQUALITY
        self._problem, self._n = problem, n
        self._model, self._cold = None, True


def _in_place(array: np.ndarray, copies) -> np.ndarray:
    """``array`` when DAQP can read it in place (C-contiguous float64), else a buffer of
    its shape, its copy appended to ``copies``."""
    if array.dtype == np.float64 and array.flags.c_contiguous:
        return array
    buffer = np.empty(array.shape)
    copies.append((array, buffer))
    return buffer
