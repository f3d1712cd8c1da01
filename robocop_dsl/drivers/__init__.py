"""Drivers that run in their own threads, and the buffers that carry copies between a
world's controller thread and them.

- :class:`AsyncWorldReader` / :class:`AsyncWorldWriter`: double-buffered,
  lock-protected copies of a joint group's command and state;
- :class:`ThreadedSimulatedDriver`: a perfect robot integrated in its own thread;
- :class:`LoopbackDriver`: a robot in another process (``python -m
  robocop_dsl.drivers.simulator``) reached over TCP on 127.0.0.1;
- :func:`create_driver`: the driver a world's ``processors:`` describe.

:class:`RobotSimulator` is imported on first use, so that ``python -m
robocop_dsl.drivers.simulator`` runs the module once, as ``__main__`` only.
"""

from __future__ import annotations

from .base import ThreadedDriver
from .buffers import AsyncWorldReader, AsyncWorldWriter, JointCommand, JointState
from .errors import DriverConfigError, DriverFault, ThreadOwnershipError
from .factory import DRIVER_OPTIONS, create_driver, driver_processor
from .loopback import LoopbackDriver
from .process import SimulatorProcess
from .simulated import ThreadedSimulatedDriver

__all__ = [
    "AsyncWorldReader",
    "AsyncWorldWriter",
    "DRIVER_OPTIONS",
    "DriverConfigError",
    "DriverFault",
    "JointCommand",
    "JointState",
    "LoopbackDriver",
    "RobotSimulator",
    "SimulatorProcess",
    "ThreadOwnershipError",
    "ThreadedDriver",
    "ThreadedSimulatedDriver",
    "create_driver",
    "driver_processor",
]


def __getattr__(name: str):
    if name == "RobotSimulator":
        from .simulator import RobotSimulator

        return RobotSimulator
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
