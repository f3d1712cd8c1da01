"""The threaded simulated driver: a perfect velocity-controlled robot integrated in a
thread of its own at its own rate."""

from __future__ import annotations

import time

import numpy as np
import pinocchio as pin

from .base import DEFAULT_COMMAND_TIMEOUT, ThreadedDriver
from .timing import Ticker

DEFAULT_PERIOD = 1e-3


class ThreadedSimulatedDriver(ThreadedDriver):
    """The state follows the commanded joint velocities exactly, integrated over the
    wall-clock time between the driver thread's cycles. The robot keeps its
    configuration from one connection to the next. The driver thread integrates on
    its own copy of the model, so the world's model stays its controller thread's.

    A command older than ``command_timeout`` (or none at all) makes the robot hold:
    zero velocity, ``holding`` set in the published state.

    Args:
        world: The world (its model gives the configuration space).
        joint_group: The driven group's name.
        period: The driver thread's period [s] (1 ms: 1 kHz).
        command_timeout: Age [s] beyond which a command is ignored.
        **kwargs: ``state_timeout``, ``connect_timeout``, ``initial`` of
            :class:`~robocop_dsl.drivers.base.ThreadedDriver`.
    """

    def __init__(self, world, joint_group: str, period: float = DEFAULT_PERIOD,
                 command_timeout: float = DEFAULT_COMMAND_TIMEOUT, **kwargs):
        super().__init__(world, joint_group, **kwargs)
        self.period = float(period)
        self.command_timeout = float(command_timeout)
        self.cycles = 0
        self.missed = 0
        self._robot_q = self.initial.copy()
        self._robot_model = pin.Model(self.model)

    def __repr__(self) -> str:
        return (f"ThreadedSimulatedDriver({self.group.name}, {self.group.dofs} dofs, "
                f"{1 / self.period:g} Hz)")

    def _serve(self) -> None:
        q = self._robot_q
        model = self._robot_model
        velocity = np.zeros(model.nv)
        group_v = self.group.v_indices
        ticker = Ticker(self.period)
        last = time.monotonic()
        self._publish(q[self.group.q_indices], velocity[group_v], True, last)
        while not self._stop.is_set():
            now = ticker.wait(self._stop)
            q = pin.integrate(model, q, velocity * (now - last))
            last = now
            command = self.reader.sync()
            holding = command is None or now - command.time > self.command_timeout
            velocity[group_v] = 0.0 if holding else command.velocity
            self._publish(q[self.group.q_indices], velocity[group_v], holding, now)
            self.cycles += 1
            self.missed = ticker.missed
        self._robot_q = q
