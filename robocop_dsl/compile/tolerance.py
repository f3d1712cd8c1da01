"""A task's compiled ``tolerance``: its defaults filled in, in SI."""

from __future__ import annotations

from ..check.context import Joints
from ..check.values import space_dimensions, to_si, vector_to_si
from ..lang import ast
from ..lang.catalogue import (DEFAULT_JOINT_TOLERANCE, DEFAULT_TOLERANCE, POSITION,
                              TOLERANCES)
from ..lang.units import ANGLE, LENGTH, lookup


def tolerance_spec(value: ast.Value | None, space: str, joints: Joints | None
                   ) -> tuple[float, ...]:
    """The tolerance [SI] of a task of ``space`` given ``value`` (checked; ``None``:
    the defaults): one per dof for joint tasks, one per part for body tasks (position
    then orientation, linear then angular)."""
    if joints is not None:
        if value is None:
            return tuple(DEFAULT_JOINT_TOLERANCE[LENGTH if kind == "prismatic" else ANGLE]
                         for kind in _per_dof(joints))
        if isinstance(value, ast.Quantity):
            return (to_si(value),) * joints.dofs
        return vector_to_si(value)
    parts = next((TOLERANCES.get(n) for n in TOLERANCES.names()
                  if TOLERANCES.get(n).space == space), None)
    dimensions = tuple(p.dimension for p in parts.parameters) if parts else \
        space_dimensions(POSITION, space, None)
    result = [DEFAULT_TOLERANCE[d] for d in dimensions]
    if isinstance(value, ast.Quantity):
        unit = lookup(value.unit.text) if value.unit else None
        index = dimensions.index(unit.dimension) if unit else 0
        result[index] = to_si(value)
    elif isinstance(value, ast.Call):
        names = [p.name for p in parts.parameters]
        for index, argument in enumerate(value.arguments):
            slot = names.index(argument.name.text) if argument.name else index
            result[slot] = to_si(argument.value)
    return tuple(result)


def _per_dof(joints: Joints) -> tuple[str, ...]:
    """The joint type of each dof (a group's dofs are its one-dof joints in order;
    otherwise every dof takes the group's own dimension)."""
    if len(joints.joint_types) == joints.dofs:
        return joints.joint_types
    return ("prismatic" if joints.position_dimensions == (LENGTH,) else "revolute",) \
        * joints.dofs
