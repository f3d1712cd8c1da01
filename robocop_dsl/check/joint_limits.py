"""Joint velocity limits above the world's: the URDF's limit wins, and ``check`` says so.

A ``joint_kinematic`` constraint never lets a joint go faster than its URDF velocity
limit, whatever its ``max_velocity``; a value above that limit is accepted but has no
effect on that joint, which is worth a warning.
"""

from __future__ import annotations

import math

from ..lang import ast
from .context import CheckContext
from .values import to_si, vector_to_si


def check_joint_limits(ctx: CheckContext, mission: ast.Mission) -> None:
    """Warn at each ``max_velocity`` of a ``joint_kinematic`` constraint that exceeds
    a joint's URDF limit [rad/s or m/s], naming the first such joint."""
    if not ctx.world.known:
        return
    for decl in mission.constraints:
        if decl.kind.text != "joint_kinematic" or len(decl.arguments) != 1:
            continue
        joints = ctx.world.joints(decl.arguments[0].text)
        if joints is None:
            continue
        for parameter in decl.parameters:
            if parameter.name.text == "max_velocity":
                _compare(ctx, decl, parameter.value, joints)


def _compare(ctx: CheckContext, decl: ast.ConstraintDecl, value: ast.Value, joints) -> None:
    if isinstance(value, ast.Quantity):
        given = (to_si(value),) * joints.dofs
    elif isinstance(value, ast.Vector) and len(value.values) == joints.dofs:
        given = vector_to_si(value)
    else:
        return
    above = [i for i, (v, limit) in enumerate(zip(given, joints.max_velocity))
             if math.isfinite(limit) and v > limit]
    if not above:
        return
    first = above[0]
    unit = "m/s" if joints.joint_types[first] == "prismatic" else "rad/s"
    names = [joint.name for joint in ctx.world.world.moving_joints(joints.name)] \
        if ctx.world.world.has_group(joints.name) else (joints.name,)
    more = f" (and {len(above) - 1} more joints)" if len(above) > 1 else ""
    ctx.warning("limit-above-urdf",
                f"max_velocity of constraint '{decl.name.text}' is above the URDF's limit "
                f"of joint '{names[first]}': {given[first]:.4g} > "
                f"{joints.max_velocity[first]:.4g} {unit}{more}", value.span,
                "the URDF's limit wins: a joint never goes faster than the lower of the two")
