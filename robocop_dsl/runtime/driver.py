"""The simulated driver: RoboCoP's ``read()``/``write()`` driver that integrates the last
velocity command of its joint group over the control period."""

from __future__ import annotations

import numpy as np
import pinocchio as pin


class SimulatedDriver:
    """A perfect robot: the state follows the commanded joint velocities exactly.

    Args:
        world: The world (its model gives the configuration space).
        joint_group: The driven group's name (from ``processors: driver: options``).
        time_step: Integration step [s], the control period.
        initial: Initial configuration (nq); defaults to the world's ``initial:``.
    """

    realtime = False
    """Time advances one ``time_step`` per ``read()``: a loop may run faster than real time."""

    def __init__(self, world, joint_group: str, time_step: float,
                 initial: np.ndarray | None = None):
        self.world = world
        self.model = world.model
        self.group = world.joint_group(joint_group)
        self.time_step = float(time_step)
        self.q = np.array(world.initial_configuration() if initial is None else initial,
                          dtype=float)
        self._velocity = np.zeros(self.model.nv)
        self._command = np.zeros(self.group.dofs)

    def __repr__(self) -> str:
        return f"SimulatedDriver({self.group.name}, {self.group.dofs} dofs, dt={self.time_step}s)"

    def connect(self) -> None:
        """Nothing to reach: the robot is this object."""

    def disconnect(self) -> None:
        """Nothing to release."""

    def read(self) -> tuple:
        """Integrate the last command over one step; return ``(q, v)`` (copies)."""
        self._velocity[self.group.v_indices] = self._command
        if self._command.any():
            self.q = pin.integrate(self.model, self.q, self._velocity * self.time_step)
        return self.q.copy(), self._velocity.copy()

    def write(self, velocity: np.ndarray) -> None:
        """Set the group's joint-velocity command [rad/s or m/s]."""
        self._command = np.array(velocity, dtype=float)

    def hold(self) -> None:
        """Command zero velocity."""
        self._command = np.zeros(self.group.dofs)

    def set_pose(self, body: str, pose) -> None:
        """Put free ``body`` at ``pose`` (world frame): nothing else moves it here."""
        self.world.place_free(self.q, body, pose)
