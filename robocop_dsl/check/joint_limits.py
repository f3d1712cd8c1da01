"""The world's joint limits against the mission: a ``max_velocity`` above a URDF
velocity limit, and a start posture outside the position limits.

A ``joint_kinematic`` constraint never lets a joint go faster than its URDF velocity
limit, whatever its ``max_velocity``; a value above that limit is accepted but has no
effect on that joint, which is worth a warning. A driven joint that starts further past
a position limit than its controller's ``state_tolerance`` makes the run refuse its
first state: an error.
"""

from __future__ import annotations

import math

from ..lang import ast
from ..safety.robot_state import DEFAULT_TOLERANCE, PRISMATIC_SHARE
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
    """At the mission's ``world`` line, for each revolute or prismatic joint the world
    starts outside its URDF position limits [rad or m]: an error when a controller drives
    it and it is further out than that controller's ``state_tolerance`` (or not a
    number: the run would refuse its first state), else a warning (the controller
    brings it back)."""
    declared = mission.first(ast.WorldDecl)
    world = ctx.world.world if ctx.world.known else None
    if world is None or declared is None:
        return
    tolerances = _state_tolerances(world)
    for name in world.joint_names():
        info = world.joint(name)
        if info.type not in ("revolute", "prismatic"):
            continue
        value = float(world.initial_position(name)[0])
        low, high = float(info.lower[0]), float(info.upper[0])
        if low - 1e-9 <= value <= high + 1e-9:
            continue
        hint = ("give it a start within its limits in the world's initial: (a joint whose "
                "zero lies outside its range needs one)")
        if not math.isfinite(value):
            ctx.error("start-outside-limits", f"the world starts joint '{name}' at "
                      f"{value}", declared.span, hint)
            continue
        bound, side = (low, "lower") if value < low else (high, "upper")
        message = f"the world starts joint '{name}' at {value:.4g}, past its {side} limit " \
                  f"{bound:.4g}"
        tolerance = tolerances.get(name)
        if tolerance is None:
            ctx.warning("start-outside-limits", message, declared.span, hint)
            continue
        tolerance *= PRISMATIC_SHARE if info.type == "prismatic" else 1.0
        if abs(value - bound) <= tolerance:
            ctx.warning("start-outside-limits", message + ", within the controller's "
                        f"state_tolerance {tolerance:.4g}", declared.span, hint)
        else:
            ctx.error("start-outside-limits", message + ": further than the controller's "
                      f"state_tolerance {tolerance:.4g}, so the run would refuse its first "
                      "state", declared.span, hint)


def _state_tolerances(world) -> dict[str, float]:
    """The ``state_tolerance`` [rad] of the controller that drives each joint (the
    smallest when several do)."""
    found: dict[str, float] = {}
    for processor in world.processors.values():
        group = processor.options.get("joint_group")
        if processor.type != "qp_controller" or group is None:
            continue
        tolerance = float(processor.run_options.get("state_tolerance", DEFAULT_TOLERANCE))
        try:
            joints = world.moving_joints(group)
        except KeyError:
            continue
        for joint in joints:
            found[joint.name] = min(found.get(joint.name, math.inf), tolerance)
    return found
