"""The force sensors of a run: one per ``force_sensor`` processor of the world, read
from the driver once per cycle, right after its state.

A sensor gives the wrench its body and what the body carries exert ON the environment:
``[fx, fy, fz, tx, ty, tz]``, force [N] then torque [N m] about the body's origin, in
the world frame (pressing down on a table reads a negative ``fz``). The driver measures
it: the MuJoCo driver from its contacts, a loopback robot that reports the sensor; a
driver that measures no wrench (``simulated``) leaves the sensor without a reading.

A sensor with a ``filter`` (a cutoff frequency ``fc`` [Hz]) is low-pass filtered,
first order: each cycle of period ``T`` the reading moves towards the measured wrench by
``1 - exp(-2 pi fc T)`` of the gap; the first reading is the first measure.

``contact(A, B)`` asks the driver whether a body of set ``A`` touches one of set ``B``:
a set is a body, or a joint group or joint for every body with collision geometry its
joints move (as ``collision_avoidance``'s sets).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..diagnostics import RobocopError, did_you_mean
from ..world.collisions import set_bodies


class SensorError(RobocopError):
    """A force or contact reading that cannot be given."""


@dataclass(frozen=True)
class ForceSensor:
    """A ``force_sensor`` processor: its name, its body and its filter's cutoff
    frequency [Hz] (``None``: not filtered)."""

    name: str
    body: str
    cutoff: float | None = None


class Sensors:
    """The world's force sensors and the latest reading of each.

    Args:
        world: The world; its ``force_sensor`` processors are the sensors.
    """

    def __init__(self, world):
        self.world = world
        self.sensors = tuple(ForceSensor(p.name, body, p.options.get("filter"))
                             for body, p in world.force_sensors().items())
        self._index = {sensor.body: index for index, sensor in enumerate(self.sensors)}
        self._cutoffs = np.array([s.cutoff or math.inf for s in self.sensors])
        self._readings = np.zeros((len(self.sensors), 6))
        self._read = False
        self._driver = None
        self._sets: dict = {}

    def __repr__(self) -> str:
        listed = ", ".join(f"{s.name} on {s.body}" for s in self.sensors) or "none"
        return f"Sensors({listed})"

    @property
    def bodies(self) -> tuple:
        """The bodies that have a sensor, in the world's order of processors."""
        return tuple(sensor.body for sensor in self.sensors)

    def update(self, driver, time_step: float) -> None:
        """Read every sensor from ``driver`` (just read) and filter; ``time_step`` [s]
        is the time since the previous update.

        Raises:
            Whatever the driver's ``wrench`` raises (a robot that stopped reporting).
        """
        self._driver = driver
        if not self.sensors or not hasattr(driver, "wrench"):
            return
        measured = np.array([driver.wrench(sensor.body) for sensor in self.sensors])
        if not self._read:
            self._readings[:] = measured
            self._read = True
            return
        step = -np.expm1(-2 * math.pi * self._cutoffs * time_step)
        self._readings += step[:, None] * (measured - self._readings)

    def wrench(self, body: str) -> np.ndarray:
        """The latest reading of the sensor on ``body``: ``[fx, fy, fz, tx, ty, tz]``
        [N, N m], what the body exerts on the environment, in the world frame.

        Raises:
            SensorError: no sensor on ``body``, or no reading (the driver measures no
                wrench, or no cycle has read it yet).
        """
        index = self._index.get(body)
        if index is None:
            listed = ", ".join(f"'{s.body}' ({s.name})" for s in self.sensors) or "none"
            close = did_you_mean(body, self.bodies)
            raise SensorError(f"no force sensor on '{body}'{f' ({close})' if close else ''}; "
                              f"bodies with one: {listed} (add a force_sensor processor "
                              "to the world)")
        if not self._read:
            raise SensorError(f"force sensor '{self.sensors[index].name}' on '{body}' has no "
                              f"reading: {self._source()} measures no wrench")
        return self._readings[index].copy()

    def readings(self) -> dict:
        """Every sensor's latest reading by body (copies); empty without readings."""
        if not self._read:
            return {}
        return dict(zip(self.bodies, self._readings.copy()))

    def contact(self, first: str, second: str) -> bool:
        """Whether a body of set ``first`` touches a body of set ``second`` now.

        Raises:
            SensorError: the driver simulates no contacts, or a name is neither a body,
                a joint group nor a joint.
        """
        if not hasattr(self._driver, "contact"):
            raise SensorError(f"contact({first}, {second}) needs a driver that simulates "
                              f"contacts: {self._source()} does not (run on a mujoco driver)")
        key = (first, second)
        sets = self._sets.get(key)
        if sets is None:
            sets = self._sets[key] = (self._bodies(first), self._bodies(second))
        return bool(self._driver.contact(*sets))

    def _bodies(self, name: str) -> tuple:
        try:
            return set_bodies(self.world, name)
        except KeyError:
            names = self.world.body_names() + self.world.group_names()
            close = did_you_mean(name, names)
            raise SensorError(f"'{name}' is neither a body, a joint group nor a joint of "
                              f"the world{f' ({close})' if close else ''}") from None

    def _source(self) -> str:
        return "no driver" if self._driver is None else f"the driver {self._driver!r}"
