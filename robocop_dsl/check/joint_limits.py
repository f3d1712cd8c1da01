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


def check_start_posture(ctx: CheckContext, mission: ast.Mission) -> None:
    """Warn, at the mission's ``world`` line, for each revolute or prismatic joint the
    world starts outside its URDF position limits [rad or m]: the run would begin past
    a limit (the controller then only brings the joint back)."""
    declared = mission.first(ast.WorldDecl)
    world = ctx.world.world if ctx.world.known else None
    if world is None or declared is None:
        return
    for name in world.joint_names():
        info = world.joint(name)
        if info.type not in ("revolute", "prismatic"):
            continue
        value = float(world.initial_position(name)[0])
        low, high = float(info.lower[0]), float(info.upper[0])
        if low - 1e-9 <= value <= high + 1e-9:
            continue
        bound, side = (low, "lower") if value < low else (high, "upper")
        ctx.warning("start-outside-limits", f"the world starts joint '{name}' at "
                    f"{value:.4g}, past its {side} limit {bound:.4g}", declared.span,
                    "give it a start within its limits in the world's initial: (a joint "
                    "whose zero lies outside its range needs one)")
