"""A task's ``tolerance``: how close to its target it counts as reached.

Joint tasks take one number or one per dof, of the joints' position (or velocity)
dimension. Body tasks with one part take one number: a length (``body_position``), an
angle (``body_orientation``, ``gaze``). ``body_pose`` and ``body_velocity`` have two parts,
each also given alone as one number of its dimension (``tolerance = 2 mm``), or both as
``pose(position = 2 mm, orientation = 1 deg)`` / ``twist(linear = 1 mm/s, angular = 1
deg/s)``.
"""

from __future__ import annotations

from ..lang import ast
from ..lang.catalogue import (JOINT_SPACE, JOINT_VELOCITY_SPACE, POSITION, POSITIVE,
                              TOLERANCES, VELOCITY)
from ..lang.units import describe, lookup
from .context import CheckContext, Joints
from .values import check_per_dof, check_quantity, space_dimensions


def check_tolerance(ctx: CheckContext, value: ast.Value, space: str | None,
                    joints: Joints | None, what: str) -> None:
    """Report what is wrong with ``value`` as the tolerance of a task of ``space``."""
    parts = next((TOLERANCES.get(n) for n in TOLERANCES.names()
                  if TOLERANCES.get(n).space == space), None)
    if isinstance(value, ast.Call) and parts is not None:
        _check_parts(ctx, value, parts, what)
        return
    if space in (JOINT_SPACE, JOINT_VELOCITY_SPACE):
        symbol = VELOCITY if space == JOINT_VELOCITY_SPACE else POSITION
        numbers = check_per_dof(ctx, value, space_dimensions(symbol, space, joints), what,
                                joints.dofs if joints else None)
        _check_positive(ctx, numbers, value, what)
        return
    dimensions = tuple(p.dimension for p in parts.parameters) if parts else \
        space_dimensions(POSITION, space, None)
    if not isinstance(value, ast.Quantity):
        both = (f"; both parts: {parts.name}("
                + ", ".join(f"{p.name} = ..." for p in parts.parameters) + ")"
                if parts else "")
        ctx.error("wrong-value", f"{what} expects {describe(dimensions)}", value.span,
                  f"one number with its unit{both}")
        return
    if parts is not None:
        unit = lookup(value.unit.text) if value.unit else None
        if unit is None or unit.dimension not in dimensions:
            given = "has no unit" if value.unit is None else \
                f"is not {describe(dimensions)}" if unit else None
            if given is not None:
                ctx.error("wrong-dimension" if unit else "wrong-value",
                          f"{what} {given}: its unit tells the part it sets",
                          (value.unit or value).span,
                          f"{describe(dimensions[:1])} sets the {parts.parameters[0].name} "
                          f"part, {describe(dimensions[1:])} the {parts.parameters[1].name} "
                          f"part; both: {parts.name}(" + ", ".join(
                              f"{p.name} = ..." for p in parts.parameters) + ")")
                return
    number = check_quantity(ctx, value, dimensions, what)
    numbers = None if number is None else (number,)
    _check_positive(ctx, numbers, value, what)


def _check_parts(ctx: CheckContext, call: ast.Call, kind, what: str) -> None:
    if call.kind.text != kind.name:
        ctx.error("wrong-value", f"{what} of both parts is written {kind.name}(...), not "
                  f"{call.kind.text}(...)", call.kind.span,
                  f"{kind.name}(" + ", ".join(f"{p.name} = ..." for p in kind.parameters)
                  + ")")
        return
    seen = set()
    for index, argument in enumerate(call.arguments):
        if argument.name is None:
            parameter = kind.parameters[index] if index < len(kind.parameters) else None
        else:
            parameter = kind.parameter(argument.name.text)
        if parameter is None:
            if argument.name is None:
                ctx.error("wrong-arguments", f"{kind.name}() takes at most "
                          f"{len(kind.parameters)} arguments", argument.value.span)
            else:
                ctx.unknown("unknown-parameter", "parameter", argument.name,
                            kind.parameter_names, f"{kind.name} takes "
                            + ", ".join(kind.parameter_names), where=f" for {kind.name}()")
            continue
        if parameter.name in seen:
            ctx.error("duplicate-name", f"parameter '{parameter.name}' is given twice",
                      (argument.name or argument.value).span)
            continue
        seen.add(parameter.name)
        part = f"{what} ({parameter.name})"
        if not isinstance(argument.value, ast.Quantity):
            ctx.error("wrong-value", f"{part} expects {describe((parameter.dimension,))}",
                      argument.value.span, "one number with its unit")
            continue
        number = check_quantity(ctx, argument.value, (parameter.dimension,), part)
        _check_positive(ctx, None if number is None else (number,), argument.value, part)


def _check_positive(ctx: CheckContext, numbers, value: ast.Value, what: str) -> None:
    """A tolerance of zero is never met: every number must be above zero."""
    if numbers is None:
        return
    bad = [i for i, n in enumerate(numbers) if POSITIVE.fault(n)]
    if not bad:
        return
    where = f": value {bad[0] + 1}" if isinstance(value, ast.Vector) else ""
    ctx.error("wrong-value", f"{what}{where} {POSITIVE.fault(numbers[bad[0]])}", value.span,
              f"valid values: {POSITIVE.text}; a tolerance of zero is never met")
