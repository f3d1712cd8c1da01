"""Numbers, vectors and their units: check dimensions, convert to SI.

Each ``check_*`` function reports what is wrong with a value and returns it in SI, or
``None`` when it is unusable. ``to_si`` and ``vector_to_si`` convert values that passed.
"""

from __future__ import annotations

from ..lang import ast
from ..lang.catalogue import (ACCELERATION, FORCE_SPACE, GAZE_SPACE, JERK, JOINT_SPACE,
                              JOINT_VELOCITY_SPACE, ORIENTATION_SPACE, POSITION, TWIST_SPACE,
                              VELOCITY)
from ..lang.units import (ANGLE, ANGULAR_ACCELERATION, ANGULAR_JERK, ANGULAR_VELOCITY,
                          DIMENSIONLESS, FORCE, LENGTH, LINEAR_ACCELERATION, LINEAR_JERK,
                          LINEAR_VELOCITY, SI_SYMBOL, UNITS, describe, lookup)
from .context import CheckContext, Joints, finite

_LENGTHS = {3: "write three values: [x, y, z] or [roll, pitch, yaw]",
            6: "write six values: [vx, vy, vz, wx, wy, wz]"}
_RATES = {ANGLE: (ANGULAR_VELOCITY, ANGULAR_ACCELERATION, ANGULAR_JERK),
          LENGTH: (LINEAR_VELOCITY, LINEAR_ACCELERATION, LINEAR_JERK)}
_RATE_INDEX = {VELOCITY: 0, ACCELERATION: 1, JERK: 2}


def space_dimensions(symbol: str, space: str | None, joints: Joints | None) -> tuple[str, ...]:
    """Turn ``POSITION`` or a rate (``VELOCITY``, ``ACCELERATION``, ``JERK``) into
    dimensions for a space; a force task's ``POSITION`` is a force."""
    if symbol != POSITION and symbol not in _RATE_INDEX:
        return (symbol,)
    if space == FORCE_SPACE and symbol == POSITION:
        return (FORCE,)
    if space in (JOINT_SPACE, JOINT_VELOCITY_SPACE):
        positions = joints.position_dimensions if joints else (ANGLE, LENGTH)
    elif space in (ORIENTATION_SPACE, GAZE_SPACE):
        positions = (ANGLE,)
    elif space == TWIST_SPACE:
        positions = (LENGTH, ANGLE)
    else:
        positions = (LENGTH,)
    if symbol == POSITION:
        return positions
    return tuple(_RATES[p][_RATE_INDEX[symbol]] for p in positions)


def unit_of(ctx: CheckContext, unit: ast.Name | None):
    """The unit named (``None`` for a bare number); ``False`` when it does not exist."""
    if unit is None:
        return None
    found = lookup(unit.text)
    if found is None:
        ctx.unknown("unknown-unit", "unit", unit, UNITS,
                    "units: " + ", ".join(UNITS))
        return False
    return found


def _dimension_fits(ctx: CheckContext, unit, written: ast.Name | None,
                    dimensions: tuple[str, ...], what: str) -> bool:
    if unit is None or unit.dimension in dimensions:
        return True
    if dimensions == (DIMENSIONLESS,):
        message = f"{what} is a plain number, not {_article(unit.dimension)}"
    else:
        message = f"{what} expects {describe(dimensions)}, not {_article(unit.dimension)}"
    ctx.error("wrong-dimension", message, written.span, _hint(dimensions))
    return False


def _article(dimension: str) -> str:
    return ("an " if dimension[0] in "aeiou" else "a ") + dimension


def _hint(dimensions: tuple[str, ...]) -> str | None:
    if dimensions == (DIMENSIONLESS,):
        return "write the number without a unit"
    return "a number without a unit is SI (" + ", ".join(
        SI_SYMBOL[d] for d in dimensions) + ")"


def check_quantity(ctx: CheckContext, quantity: ast.Quantity, dimensions: tuple[str, ...],
                   what: str) -> float | None:
    """A scalar of one of ``dimensions``, in SI."""
    unit = unit_of(ctx, quantity.unit)
    if unit is False:
        return None
    if not _dimension_fits(ctx, unit, quantity.unit, dimensions, what):
        return None
    if not finite(quantity.value):
        ctx.error("bad-number", f"{what} is too large", quantity.span)
        return None
    return to_si(quantity)


def check_vector(ctx: CheckContext, vector: ast.Vector, dimensions: tuple[str, ...], what: str,
                 length: int | None) -> tuple[float, ...] | None:
    """A vector of ``length`` values (any when ``None``) of one of ``dimensions``, in SI;
    ``None`` for a vector with a name left unbound (reported where it was bound) or
    holding vars (checked here: only a target may hold them)."""
    if not all(isinstance(v, float) for v in vector.values):
        _check_var_elements(ctx, vector, dimensions, what)
        return None
    unit = unit_of(ctx, vector.unit)
    if unit is False:
        return None
    if not _dimension_fits(ctx, unit, vector.unit, dimensions, what):
        return None
    if length is not None and len(vector.values) != length:
        ctx.error("wrong-length", f"{what} has {len(vector.values)} values, expected {length}",
                  vector.span, _LENGTHS.get(length, f"one value per degree of freedom "
                                                    f"({length})"))
        return None
    if not all(map(finite, vector.values)):
        ctx.error("bad-number", f"{what} has a value too large", vector.span)
        return None
    return vector_to_si(vector)


def _check_var_elements(ctx: CheckContext, vector: ast.Vector, dimensions: tuple[str, ...],
                        what: str) -> None:
    """The vars a vector holds: visible, one number of one of ``dimensions``, in a
    target set by an action."""
    from .variables import NAMED, describe as describe_value

    wanted = {NAMED[d] for d in dimensions if d in NAMED}
    for element in vector.values:
        if not isinstance(element, ast.NameElement) or element.name.text in ctx.generic \
                or element.name.text not in ctx.all_variables:
            continue
        info = ctx.variables.get(element.name.text)
        if not ctx.in_target:
            ctx.error("wrong-value", f"{what} cannot hold the var '{element.name.text}'",
                      element.name.span, "a var is read in a target set by an action, a "
                      "condition, an assignment or a log; a declaration takes constants")
        elif info is None:
            ctx.unknown("unknown-var", "var", element.name, ctx.variables,
                        "declare it: var NAME: KIND = VALUE")
        elif info.typed.size != 1 or info.typed.dimension not in wanted:
            ctx.error("wrong-dimension", f"{what} holds {describe(dimensions)}, "
                      f"not {describe_value(info.typed.dimension, info.typed.size)} like "
                      f"'{element.name.text}'", element.name.span, "use a var of that kind")


def check_offset(ctx: CheckContext, offset: ast.Offset) -> tuple[float, ...] | None:
    """The 3-vector [m] of ``BODY offset VECTOR``; a name left unbound is reported."""
    vector = offset.offset
    if isinstance(vector, ast.Reference):
        if vector.name.text not in ctx.generic:
            ctx.unknown("unknown-name", "constant", vector.name, ctx.vectors,
                        "an offset is a vector of lengths, or a constant that holds one")
        return None
    if not isinstance(vector, ast.Vector):
        ctx.error("wrong-value", "an offset is a vector of three lengths", vector.span,
                  "for example [0, 0, 10] cm")
        return None
    return check_vector(ctx, vector, (LENGTH,), "an offset", 3)


def check_per_dof(ctx: CheckContext, value: ast.Value, dimensions: tuple[str, ...], what: str,
                  dofs: int | None) -> tuple[float, ...] | None:
    """One number broadcast over ``dofs``, or a vector of one per dof, in SI."""
    if isinstance(value, ast.Quantity):
        number = check_quantity(ctx, value, dimensions, what)
        return None if number is None else (number,) * (dofs or 1)
    if isinstance(value, ast.Vector):
        return check_vector(ctx, value, dimensions, what, dofs)
    ctx.error("wrong-value", f"{what} expects {describe(dimensions)}", value.span,
              "a number with a unit, or a vector of one per joint")
    return None


def to_si(quantity: ast.Quantity) -> float:
    unit = lookup(quantity.unit.text) if quantity.unit else None
    return quantity.value * (unit.to_si if unit else 1.0)


def vector_to_si(vector: ast.Vector) -> tuple[float, ...]:
    unit = lookup(vector.unit.text) if vector.unit else None
    scale = unit.to_si if unit else 1.0
    return tuple(v * scale for v in vector.values)
