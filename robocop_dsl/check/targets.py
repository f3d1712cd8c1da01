"""Task targets: the right kind of target for the task, of the right size, within limits.

Targets by space: joint tasks take a vector of one value per joint (or ``current``);
``body_position`` a 3-vector [m], a body, ``BODY offset [x, y, z]`` or ``pose(position)``;
``body_orientation`` roll-pitch-yaw [rad], a body or ``pose(rpy)``; ``body_pose`` a body,
an offset body or ``pose(position, rpy)``; ``body_velocity`` a 6-vector in SI (linear
then angular); ``gaze`` a body, an offset body or a point [m]; ``body_force`` a force
[fx, fy, fz] in the world frame. ``current`` holds the value the task has when the
target is set.
"""

from __future__ import annotations

from ..diagnostics import did_you_mean
from ..lang import ast
from ..lang.catalogue import (FORCE_SPACE, GAZE_SPACE, JOINT_SPACE, JOINT_VELOCITY_SPACE,
                              ORIENTATION_SPACE, POSE_SPACE, POSITION, POSITION_SPACE,
                              TWIST_SPACE, VELOCITY, Kind)
from ..lang.units import ANGLE, FORCE, LENGTH
from .context import CheckContext, Joints
from .values import check_offset, check_vector, space_dimensions

CURRENT = "current"
POSE_ARGUMENTS = ("position", "rpy")
_TOLERANCE = 1e-9

_FORMS = {
    JOINT_SPACE: "a vector of joint positions or 'current'",
    JOINT_VELOCITY_SPACE: "a vector of joint velocities or 'current'",
    POSITION_SPACE: "a body, 'BODY offset [x, y, z] m', a position [x, y, z] m, "
                    "pose(position = ...) or 'current'",
    ORIENTATION_SPACE: "a body, roll-pitch-yaw angles [r, p, y] deg, pose(rpy = ...) "
                       "or 'current'",
    POSE_SPACE: "a body, 'BODY offset [x, y, z] m', pose(position = [...] m, "
                "rpy = [...] deg) or 'current'",
    TWIST_SPACE: "a velocity [vx, vy, vz, wx, wy, wz] in SI or 'current'",
    GAZE_SPACE: "a body, 'BODY offset [x, y, z] m', a point [x, y, z] m or 'current'",
    FORCE_SPACE: "a force [fx, fy, fz] N in the world frame or 'current'",
}
_ALLOWED = {
    JOINT_SPACE: {ast.Vector}, JOINT_VELOCITY_SPACE: {ast.Vector},
    POSITION_SPACE: {ast.Vector, ast.Reference, ast.Offset, ast.Call},
    ORIENTATION_SPACE: {ast.Vector, ast.Reference, ast.Call},
    POSE_SPACE: {ast.Reference, ast.Offset, ast.Call},
    TWIST_SPACE: {ast.Vector},
    GAZE_SPACE: {ast.Vector, ast.Reference, ast.Offset},
    FORCE_SPACE: {ast.Vector},
}
_POSE_PARTS = {POSITION_SPACE: ("position",), ORIENTATION_SPACE: ("rpy",),
               POSE_SPACE: POSE_ARGUMENTS}


def check_target(ctx: CheckContext, value: ast.Value, kind: Kind, joints: Joints | None,
                 what: str) -> None:
    """Check ``value`` as a target of a task of type ``kind`` driving ``joints``."""
    space = kind.space
    if isinstance(value, ast.Reference) and value.name.text == CURRENT:
        return
    if isinstance(value, ast.Quantity) and space in (JOINT_SPACE, JOINT_VELOCITY_SPACE) \
            and joints is not None and joints.dofs == 1:
        value = ast.Vector((value.value,), value.unit, span=value.span)
    if type(value) not in _ALLOWED.get(space, ()):
        _wrong(ctx, value, kind, joints)
        return
    if isinstance(value, ast.Reference):
        _check_body_target(ctx, value.name)
    elif isinstance(value, ast.Offset):
        if _check_body_target(ctx, value.body):
            check_offset(ctx, value)
    elif isinstance(value, ast.Call):
        _check_pose(ctx, value, space, kind)
    elif space in (JOINT_SPACE, JOINT_VELOCITY_SPACE):
        _check_joint_vector(ctx, value, space, joints, what)
    elif space == TWIST_SPACE:
        if value.unit is not None:
            ctx.error("wrong-dimension", "a body velocity target mixes m/s and rad/s: "
                      "write it without a unit, in SI", value.unit.span)
        else:
            check_vector(ctx, value, (LENGTH,), what, 6)
    else:
        dimension = {ORIENTATION_SPACE: ANGLE, FORCE_SPACE: FORCE}.get(space, LENGTH)
        check_vector(ctx, value, (dimension,), what, 3)


def _wrong(ctx: CheckContext, value: ast.Value, kind: Kind, joints: Joints | None) -> None:
    found = {ast.Vector: "a vector", ast.Quantity: "a number", ast.Reference: "a name",
             ast.Offset: "an offset body", ast.Call: "a call", ast.String: "a string"}
    shown = found[type(value)]
    if isinstance(value, ast.Reference) and ctx.world.has_body(value.name.text) \
            and ctx.world.known:
        shown = f"a body ('{value.name.text}')"
    if isinstance(value, ast.Quantity) and joints is not None:
        ctx.error("wrong-length", f"a {kind.name} target needs {joints.dofs} values, "
                  "not one number", value.span, f"write {_FORMS[kind.space]}")
        return
    if isinstance(value, ast.Reference) and not ctx.world.has_body(value.name.text):
        near = did_you_mean(value.name.text, [*ctx.constants, *ctx.variables])
        if near:
            ctx.error("unknown-name", f"unknown constant or var '{value.name.text}'",
                      value.span, near)
            return
    ctx.error("wrong-target", f"{shown} is not a target for a {kind.name} task",
              value.span, f"a {kind.name} target is {_FORMS[kind.space]}")


def _check_body_target(ctx: CheckContext, name: ast.Name) -> bool:
    if ctx.world.has_body(name.text):
        return True
    ctx.unknown("unknown-body", "body", name, ctx.world.body_names() + [CURRENT])
    return False


def _check_pose(ctx: CheckContext, call: ast.Call, space: str, kind: Kind) -> None:
    if call.kind.text != "pose":
        ctx.error("wrong-target", f"'{call.kind.text}(...)' is not a target",
                  call.kind.span, f"a {kind.name} target is {_FORMS[space]}")
        return
    allowed = _POSE_PARTS[space]
    seen = set()
    for index, argument in enumerate(call.arguments):
        name = argument.name.text if argument.name else (
            POSE_ARGUMENTS[index] if index < len(POSE_ARGUMENTS) else None)
        span = (argument.name or argument).span
        if name not in POSE_ARGUMENTS:
            if argument.name is None:
                ctx.error("wrong-arguments", "pose() takes at most 2 arguments", span)
            else:
                ctx.unknown("unknown-parameter", "parameter", argument.name, POSE_ARGUMENTS,
                            "pose() takes position, rpy", where=" for pose()")
            continue
        if name not in allowed:
            ctx.error("wrong-target", f"a {kind.name} target has no '{name}'", span,
                      f"a {kind.name} target is {_FORMS[space]}")
            continue
        if name in seen:
            ctx.error("duplicate-name", f"parameter '{name}' is given twice", span)
            continue
        seen.add(name)
        if ctx.opaque(argument.value):
            continue
        if not isinstance(argument.value, ast.Vector):
            ctx.error("wrong-value", f"'{name}' expects a vector [x, y, z]",
                      argument.value.span)
            continue
        dimension = LENGTH if name == "position" else ANGLE
        check_vector(ctx, argument.value, (dimension,), f"'{name}'", 3)


def _check_joint_vector(ctx: CheckContext, vector: ast.Vector, space: str,
                        joints: Joints | None, what: str) -> None:
    symbol = POSITION if space == JOINT_SPACE else VELOCITY
    dimensions = space_dimensions(symbol, space, joints)
    values = check_vector(ctx, vector, dimensions, what,
                          joints.dofs if joints is not None else None)
    if values is None or joints is None:
        return
    if space == JOINT_SPACE:
        bounds = zip(joints.lower, joints.upper)
    else:
        bounds = ((-v, v) for v in joints.max_velocity)
    for index, (value, (low, high)) in enumerate(zip(values, bounds)):
        if low - _TOLERANCE <= value <= high + _TOLERANCE:
            continue
        kind = "position" if space == JOINT_SPACE else "velocity"
        unit = "m" if dimensions == (LENGTH,) else "rad"
        unit += "/s" if space == JOINT_VELOCITY_SPACE else ""
        ctx.error("outside-limits",
                  f"{what}: value {index + 1} ({value:.4g} {unit}) is outside the joint "
                  f"{kind} limits [{low:.4g}, {high:.4g}] {unit}", vector.span,
                  f"joint {index + 1} of '{joints.name}'")
