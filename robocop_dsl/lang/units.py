"""Units of the mission language: each has a dimension and a factor to SI.

A number without a unit is already SI (m, rad, s and their rates).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

LENGTH = "length"
ANGLE = "angle"
TIME = "time"
LINEAR_VELOCITY = "linear velocity"
ANGULAR_VELOCITY = "angular velocity"
LINEAR_ACCELERATION = "linear acceleration"
ANGULAR_ACCELERATION = "angular acceleration"
LINEAR_JERK = "linear jerk"
ANGULAR_JERK = "angular jerk"
FORCE = "force"
TORQUE = "torque"
ADMITTANCE = "admittance"
"""A velocity per unit of force: a force task's gain."""
DIMENSIONLESS = "dimensionless"


@dataclass(frozen=True)
class Unit:
    """A unit symbol, its dimension and the factor that converts it to SI."""

    symbol: str
    dimension: str
    to_si: float


_DEG = math.pi / 180
UNITS: dict[str, Unit] = {u.symbol: u for u in (
    Unit("m", LENGTH, 1.0), Unit("cm", LENGTH, 1e-2), Unit("mm", LENGTH, 1e-3),
    Unit("rad", ANGLE, 1.0), Unit("deg", ANGLE, _DEG),
    Unit("s", TIME, 1.0), Unit("ms", TIME, 1e-3),
    Unit("m/s", LINEAR_VELOCITY, 1.0), Unit("cm/s", LINEAR_VELOCITY, 1e-2),
    Unit("mm/s", LINEAR_VELOCITY, 1e-3),
    Unit("rad/s", ANGULAR_VELOCITY, 1.0), Unit("deg/s", ANGULAR_VELOCITY, _DEG),
    Unit("m/s^2", LINEAR_ACCELERATION, 1.0),
    Unit("rad/s^2", ANGULAR_ACCELERATION, 1.0), Unit("deg/s^2", ANGULAR_ACCELERATION, _DEG),
    Unit("m/s^3", LINEAR_JERK, 1.0), Unit("rad/s^3", ANGULAR_JERK, 1.0),
    Unit("deg/s^3", ANGULAR_JERK, _DEG),
    Unit("N", FORCE, 1.0), Unit("kN", FORCE, 1e3), Unit("mN", FORCE, 1e-3),
    Unit("Nm", TORQUE, 1.0),
    Unit("(m/s)/N", ADMITTANCE, 1.0), Unit("(cm/s)/N", ADMITTANCE, 1e-2),
    Unit("(mm/s)/N", ADMITTANCE, 1e-3),
)}

SI_SYMBOL = {LENGTH: "m", ANGLE: "rad", TIME: "s", LINEAR_VELOCITY: "m/s",
             ANGULAR_VELOCITY: "rad/s", LINEAR_ACCELERATION: "m/s^2",
             ANGULAR_ACCELERATION: "rad/s^2", LINEAR_JERK: "m/s^3", ANGULAR_JERK: "rad/s^3",
             FORCE: "N", TORQUE: "Nm", ADMITTANCE: "(m/s)/N", DIMENSIONLESS: ""}


def lookup(symbol: str) -> Unit | None:
    """The unit written ``symbol``, or ``None`` when the language has no such unit."""
    return UNITS.get(symbol)


def symbols_of(dimension: str) -> list[str]:
    """The unit symbols of a dimension, SI first."""
    return [u.symbol for u in UNITS.values() if u.dimension == dimension]


def describe(dimensions: tuple[str, ...]) -> str:
    """``"an angular velocity (rad/s, deg/s)"``: for messages naming what was expected."""
    parts = []
    for dimension in dimensions:
        if dimension == DIMENSIONLESS:
            parts.append("a plain number")
            continue
        article = "an" if dimension[0] in "aeiou" else "a"
        parts.append(f"{article} {dimension} ({', '.join(symbols_of(dimension))})")
    return " or ".join(parts)
