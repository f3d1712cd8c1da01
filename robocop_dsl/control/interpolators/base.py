"""Abstract interpolator: turns a task's target into a smooth reference."""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np


class Interpolator(ABC):
    """Generates, every control period, a reference moving towards the target.

    A task owns one interpolator and drives it: :meth:`setup` when attached,
    :meth:`restart` from the current value when the task is enabled or reset,
    :meth:`retarget` when given a new target while running, then each cycle sets
    :attr:`target` and calls :meth:`step`. Values are vectors of the task's
    coordinates (joint positions, positions, rotation vectors).

    Attributes:
        dimension: Number of coordinates.
        time_step: Control period [s].
        angular: Boolean mask of the coordinates that are rotation-vector components.
        target: The goal, updated by the task each cycle.
    """

    kind = "interpolator"
    passthrough = False
    """Whether the reference is the target itself (the task then skips stepping)."""

    def __init__(self):
        self.dimension = 0
        self.time_step = 0.0
        self.angular = np.zeros(0, dtype=bool)
        self.target = np.zeros(0)
        self.position = np.zeros(0)
        self.velocity = np.zeros(0)

    def setup(self, dimension: int, time_step: float, angular: np.ndarray) -> None:
        """Size the interpolator for a task; called once when attached."""
        self.dimension = dimension
        self.time_step = time_step
        self.angular = np.asarray(angular, dtype=bool)
        self.target = np.zeros(dimension)
        self.position = np.zeros(dimension)
        self.velocity = np.zeros(dimension)
        self.configure_limits()

    def configure_limits(self) -> None:
        """Hook run after :meth:`setup` to size limits; nothing by default."""

    def restart(self, position: np.ndarray, velocity: np.ndarray) -> None:
        """Start a new trajectory from ``position`` moving at ``velocity``."""
        self.position = np.array(position, dtype=float)
        self.velocity = np.array(velocity, dtype=float)
        self.start()

    def retarget(self) -> None:
        """The target changed mid-trajectory: by default a new trajectory starts from
        the current reference and its velocity."""
        self.restart(self.position, self.velocity)

    @abstractmethod
    def start(self) -> None:
        """Hook: begin a trajectory from :attr:`position` / :attr:`velocity`."""

    @abstractmethod
    def step(self) -> tuple[np.ndarray, np.ndarray]:
        """Advance one period; returns the reference position and velocity."""

    @property
    @abstractmethod
    def finished(self) -> bool:
        """Whether the trajectory has reached the target."""

    def parameters(self) -> dict:
        """The interpolator's parameters by name."""
        return {}

    def __repr__(self) -> str:
        arguments = ", ".join(f"{key}={_short(value)}" for key, value in self.parameters().items())
        return f"{self.kind}({arguments})"


def _short(value) -> str:
    if isinstance(value, np.ndarray):
        if value.size and np.all(value == value.flat[0]):
            return repr(float(value.flat[0]))
        return repr([round(float(v), 6) for v in value])
    return repr(value)
