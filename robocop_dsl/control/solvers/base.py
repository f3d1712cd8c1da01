"""A quadratic program in the controller's form, its solution, and the solver interface."""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field

import numpy as np

from ..exceptions import InvalidParameter


@dataclass(frozen=True, slots=True)
class QuadraticProgram:
    """``min 1/2 x'Hx + g'x  s.t.  Ax = b,  l <= Cx <= u,  lower <= x <= upper``.

    ``x`` is the joint-velocity command of the controlled group. Bounds may be
    infinite. The arrays are fixed at construction; the controller builds consistent
    shapes and rewrites the arrays' values every cycle, so a solver may keep what it
    derived from a program it already saw. :meth:`validate` checks a program built
    by hand.
    """

    H: np.ndarray
    g: np.ndarray
    A: np.ndarray
    b: np.ndarray
    C: np.ndarray
    l: np.ndarray
    u: np.ndarray
    lower: np.ndarray
    upper: np.ndarray

    def validate(self) -> "QuadraticProgram":
        """Check the shapes; returns the program.

        Raises:
            InvalidParameter: naming the first array with a wrong shape.
        """
        n, n_eq, n_in = self.g.shape[0], self.b.shape[0], self.l.shape[0]
        shapes = (self.H.shape, self.A.shape, self.C.shape, self.u.shape, self.lower.shape,
                  self.upper.shape)
        expected = ((n, n), (n_eq, n), (n_in, n), (n_in,), (n,), (n,))
        if shapes != expected:
            names = ("H", "A", "C", "u", "lower", "upper")
            name, shape, wanted = next(item for item in zip(names, shapes, expected)
                                       if item[1] != item[2])
            raise InvalidParameter("quadratic program", name, shape, f"shape {wanted}")
        return self

    @property
    def size(self) -> tuple[int, int, int]:
        """Variables, equality rows and inequality rows."""
        return self.g.shape[0], self.b.shape[0], self.l.shape[0]

    def violation(self, x: np.ndarray) -> float:
        """Largest constraint violation of ``x`` (0 when feasible)."""
        worst = max(0.0, float(np.max(self.lower - x, initial=0.0)),
                    float(np.max(x - self.upper, initial=0.0)))
        if self.b.size:
            worst = max(worst, float(np.max(np.abs(self.A @ x - self.b))))
        if self.l.size:
            cx = self.C @ x
            worst = max(worst, float(np.max(self.l - cx, initial=0.0)),
                        float(np.max(cx - self.u, initial=0.0)))
        return worst


@dataclass(slots=True)
class QPSolution:
    """A solver's answer.

    Attributes:
        found: Whether the solver reports an optimal solution.
        x: The solution (zeros when not found).
        iterations: Solver iterations, when the backend reports them.
        status: The backend's status, as text.
    """

    found: bool
    x: np.ndarray
    iterations: int = 0
    status: str = field(default="")


class QPSolver(ABC):
    """A QP backend behind one signature; instances may keep state between cycles."""

    name = "solver"
    guarantees_tolerance = False
    """Whether a reported solution is known to meet the constraints to tolerance."""

    @abstractmethod
    def solve(self, problem: QuadraticProgram) -> QPSolution:
        """Solve ``problem``; never raises on numerical failure (``found=False``)."""

    def reset(self) -> None:
        """Forget warm-start data; nothing by default."""

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r})"
