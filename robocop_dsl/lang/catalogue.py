"""The vocabulary of tasks, constraints, interpolators and feedback laws.

The grammar knows none of these names: a declaration's type is looked up here, so a new
type is one :func:`register` call away. Each type lists its parameters with the kind of
value they take, their dimension, whether they are required and their default.

Dimensions are those of :mod:`robocop_dsl.lang.units`, or one of ``POSITION``,
``VELOCITY``, ``ACCELERATION``, ``JERK``: the position or one of its rates of what the task
or constraint drives (radians or metres for a joint group depending on its joints,
metres for a body's position, radians for its orientation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Generic, TypeVar

from .units import (ADMITTANCE, ANGLE, ANGULAR_ACCELERATION, ANGULAR_JERK, ANGULAR_VELOCITY,
                    DIMENSIONLESS, FORCE, LENGTH, LINEAR_VELOCITY, TIME)

POSITION = "position"
VELOCITY = "velocity"
ACCELERATION = "acceleration"
JERK = "jerk"

# What a parameter's value is written as.
SCALAR = "scalar"            # one number with a unit
PER_DOF = "per_dof"          # one number (broadcast) or a vector of one per dof
PER_AXIS = "per_axis"        # one number (broadcast) or a vector of the task's dimension
NORM_OR_AXES = "norm_or_axes"  # one number (bounds the norm) or a 3-vector (each axis)
TOLERANCE = "tolerance"      # when a task counts as reached (see TOLERANCES)
SWITCH = "switch"            # true or false
INTEGER = "integer"          # a non-negative whole number
BODY = "body"                # a body name, or world
AXES = "axes"                # a list of the world's axes: [x, z]
INTERPOLATOR = "interpolator"
FEEDBACK = "feedback"
TARGET = "target"

# What a task or constraint drives, named by its argument.
JOINT_GROUP = "joint_group"
BODY_SUBJECT = "body"
COLLISION_SETS = "collision_sets"  # two arguments, each a body or a joint group

# Spaces: what a task's target and error are made of.
JOINT_SPACE = "joint"
JOINT_VELOCITY_SPACE = "joint_velocity"
POSITION_SPACE = "position"
ORIENTATION_SPACE = "orientation"
POSE_SPACE = "pose"
TWIST_SPACE = "twist"
GAZE_SPACE = "gaze"
FORCE_SPACE = "force"

SPACE_AXES = {POSITION_SPACE: 3, ORIENTATION_SPACE: 3, POSE_SPACE: 6, TWIST_SPACE: 6,
              GAZE_SPACE: 2, FORCE_SPACE: 3}
"""Task coordinates (error and velocity axes) of each body space; a force task's target
is a force along the three axes of the world, whatever axes it controls."""
AXIS_NAMES = ("x", "y", "z")
"""The world's axes, as an ``AXES`` parameter lists them."""
SWITCH_WORDS = ("true", "false")
DEFAULT_TOLERANCE = {LENGTH: 1e-3, ANGLE: math.radians(1.0), LINEAR_VELOCITY: 1e-3,
                     ANGULAR_VELOCITY: math.radians(1.0), FORCE: 1.0}
"""A body task's tolerance by the dimension of its part [SI]: 1 mm, 1 deg and their rates,
1 N."""
DEFAULT_JOINT_TOLERANCE = {ANGLE: math.radians(0.5), LENGTH: 1e-3}
"""A joint task's tolerance per joint by the joint's dimension [SI], also per second for
joint velocities: 0.5 deg for a rotation, 1 mm for a translation."""


@dataclass(frozen=True)
class Range:
    """The valid values of a number, in SI: ``low`` or more (above ``low`` if ``strict``)."""

    low: float = 0.0
    strict: bool = False

    @property
    def text(self) -> str:
        return f"greater than {self.low:g}" if self.strict else f"{self.low:g} or more"

    def fault(self, value: float) -> str | None:
        """What is wrong with ``value`` [SI], or ``None`` when it is in the range."""
        if value > self.low or (value == self.low and not self.strict):
            return None
        if self.low != 0:
            return f"must be {self.text}"
        return "must not be zero" if value == 0 else "must not be negative"


POSITIVE = Range(strict=True)
NON_NEGATIVE = Range()


@dataclass(frozen=True)
class Parameter:
    """One parameter: its name, how it is written, its dimension, need and default.

    ``settable`` parameters may also be changed by a state's actions (``X.gain = 2``);
    ``valid`` is the range of each of its numbers (``None``: any); ``spaces`` the task
    spaces an interpolator's parameter applies to (``None``: all).
    """

    name: str
    kind: str
    dimension: str = DIMENSIONLESS
    required: bool = False
    default: Any = None
    settable: bool = False
    valid: Range | None = None
    doc: str = ""
    spaces: tuple[str, ...] | None = None


@dataclass(frozen=True)
class Kind:
    """A task, constraint, interpolator or feedback type.

    ``subject`` is what its single argument names (a joint group or a body; ``None``
    for interpolators and feedback laws) and ``space`` what its target lives in.
    ``ordered`` lists pairs ``(low, high)`` of per-dof position parameters where each
    value of ``low`` must not exceed that of ``high``; an absent one stands for the
    joints' URDF limit (lower for ``low``, upper for ``high``). ``bounded`` lists pairs
    ``(value, bound)`` where each value's magnitude must not exceed the bound's.
    """

    name: str
    parameters: tuple[Parameter, ...]
    subject: str | None = None
    space: str | None = None
    doc: str = ""
    ordered: tuple[tuple[str, str], ...] = ()
    bounded: tuple[tuple[str, str], ...] = ()

    def parameter(self, name: str) -> Parameter | None:
        return next((p for p in self.parameters if p.name == name), None)

    @property
    def parameter_names(self) -> list[str]:
        return [p.name for p in self.parameters]


T = TypeVar("T", bound=Kind)


class Registry(Generic[T]):
    """Named kinds of one family (tasks, constraints...); ``register`` adds one."""

    def __init__(self, family: str):
        self.family = family
        self._kinds: dict[str, T] = {}

    def register(self, kind: T) -> T:
        self._kinds[kind.name] = kind
        return kind

    def get(self, name: str) -> T | None:
        return self._kinds.get(name)

    def names(self) -> list[str]:
        return list(self._kinds)


TASKS: Registry[Kind] = Registry("task type")
CONSTRAINTS: Registry[Kind] = Registry("constraint type")
INTERPOLATORS: Registry[Kind] = Registry("interpolator")
FEEDBACKS: Registry[Kind] = Registry("feedback law")


def _task_parameters(body: bool) -> tuple[Parameter, ...]:
    common = (
        Parameter("target", TARGET, settable=True, default="current",
                  doc="what to reach; default: hold the state at enable"),
        Parameter("interpolator", INTERPOLATOR, default="none",
                  doc="how the reference moves to the target"),
        Parameter("feedback", FEEDBACK, default="proportional",
                  doc="how the error becomes a velocity"),
        Parameter("priority", INTEGER, default=0, valid=NON_NEGATIVE,
                  doc="0 is highest (strict hierarchy)"),
        Parameter("weight", SCALAR, default=1.0, settable=True, valid=NON_NEGATIVE,
                  doc="relative weight (weighted hierarchy)"),
        Parameter("gain", PER_AXIS, settable=True, valid=NON_NEGATIVE,
                  doc="proportional gain [1/s] replacing the feedback's own, one number or "
                      "one per dof / per axis"),
        Parameter("tolerance", TOLERANCE, POSITION, valid=POSITIVE,
                  doc="when the task counts as reached; default 1 mm and 1 deg for body "
                      "tasks, 0.5 deg (1 mm prismatic) per joint for joint tasks"),
        Parameter("enabled", SWITCH, default=False,
                  doc="true: the task is active from the start"),
    )
    if body:
        return (Parameter("reference", BODY, default="world",
                          doc="frame the target is expressed in"),) + common
    return common


for _name, _subject, _space, _doc in (
        ("joint_position", JOINT_GROUP, JOINT_SPACE, "joint positions of a group"),
        ("joint_velocity", JOINT_GROUP, JOINT_VELOCITY_SPACE, "joint velocities of a group"),
        ("body_position", BODY_SUBJECT, POSITION_SPACE, "position of a body's origin"),
        ("body_orientation", BODY_SUBJECT, ORIENTATION_SPACE, "orientation of a body"),
        ("body_pose", BODY_SUBJECT, POSE_SPACE, "position and orientation of a body"),
        ("body_velocity", BODY_SUBJECT, TWIST_SPACE, "linear and angular velocity of a body"),
):
    TASKS.register(Kind(_name, _task_parameters(_subject == BODY_SUBJECT), _subject, _space,
                        _doc))
TASKS.register(Kind("gaze", _task_parameters(True), BODY_SUBJECT, GAZE_SPACE,
                   "point a body's z axis (a camera's optical axis) at a body or point; "
                   "its error is the angle off it"))
TASKS.register(Kind("body_force", (
    Parameter("target", TARGET, settable=True, default=(0.0, 0.0, 0.0),
              doc="the force [fx, fy, fz] the body exerts on its environment, world frame "
                  "(pressing down on a table is a negative z); default [0, 0, 0] N"),
    Parameter("axes", AXES, default=(0, 1, 2),
              doc="the world axes whose force it controls, e.g. [z]; the others are left "
                  "free; default [x, y, z]"),
    Parameter("gain", SCALAR, ADMITTANCE, required=True, settable=True, valid=NON_NEGATIVE,
              doc="admittance: the reference velocity per newton of force error"),
    Parameter("max_velocity", SCALAR, LINEAR_VELOCITY, required=True, settable=True,
              valid=POSITIVE, doc="bound on the reference velocity along each axis"),
    Parameter("tolerance", TOLERANCE, POSITION, valid=POSITIVE,
              doc="reached when the force error of every controlled axis is within it; "
                  "default 1 N"),
    *(p for p in _task_parameters(False) if p.name in ("priority", "weight", "enabled")),
), BODY_SUBJECT, FORCE_SPACE,
    "velocity-resolved force control (admittance): the body's reference velocity along "
    "each controlled axis is gain * (target - measured), bounded by max_velocity; the "
    "body needs a force sensor"))

CONSTRAINTS.register(Kind("joint_kinematic", (
    Parameter("min_position", PER_DOF, POSITION, settable=True,
              doc="default: the URDF's lower limits"),
    Parameter("max_position", PER_DOF, POSITION, settable=True,
              doc="default: the URDF's upper limits"),
    Parameter("max_velocity", PER_DOF, VELOCITY, settable=True, valid=POSITIVE,
              doc="default: the URDF's velocity limits"),
    Parameter("max_acceleration", PER_DOF, ACCELERATION, settable=True, valid=POSITIVE,
              doc="default: not limited"),
    Parameter("enabled", SWITCH, default=True,
              doc="false: the constraint is off until a state enables it"),
), JOINT_GROUP, JOINT_SPACE, "joint position, velocity and acceleration limits",
    ordered=(("min_position", "max_position"),)))

CONSTRAINTS.register(Kind("body_velocity", (
    Parameter("reference", BODY, default="world", doc="frame the velocity is measured in"),
    Parameter("max_linear", NORM_OR_AXES, LINEAR_VELOCITY, settable=True,
              valid=NON_NEGATIVE, doc="a number bounds the linear speed, a 3-vector each "
                                      "axis of the reference; default: not limited"),
    Parameter("max_angular", NORM_OR_AXES, ANGULAR_VELOCITY, settable=True,
              valid=NON_NEGATIVE, doc="a number bounds the angular speed, a 3-vector each "
                                      "axis of the reference; default: not limited"),
    Parameter("enabled", SWITCH, default=True,
              doc="false: the constraint is off until a state enables it"),
), BODY_SUBJECT, TWIST_SPACE, "bounds on a body's velocity"))

CONSTRAINTS.register(Kind("collision_avoidance", (
    Parameter("min_distance", SCALAR, LENGTH, default=0.01, settable=True,
              valid=NON_NEGATIVE, doc="never closer than this; default 1 cm"),
    Parameter("influence", SCALAR, LENGTH, default=0.1, settable=True, valid=POSITIVE,
              doc="the constraint acts on the pairs closer than this, above min_distance; "
                  "default 10 cm"),
    Parameter("damping", SCALAR, DIMENSIONLESS, default=5.0, settable=True, valid=POSITIVE,
              doc="[1/s] how fast the gap to min_distance may close: the approach speed "
                  "is at most damping times the gap; default 5"),
    Parameter("enabled", SWITCH, default=True,
              doc="false: the constraint is off until a state enables it"),
), COLLISION_SETS, doc="keep the collision geometry of two sets of bodies (a body, or a "
                       "joint group for every body its joints move) apart"))

ROTATION_SPACES = (ORIENTATION_SPACE, POSE_SPACE, TWIST_SPACE, GAZE_SPACE)

INTERPOLATORS.register(Kind("otg", (
    Parameter("max_velocity", PER_DOF, VELOCITY, required=True, valid=POSITIVE,
              doc="for a body pose or twist, of the position only"),
    Parameter("max_acceleration", PER_DOF, ACCELERATION, required=True, valid=POSITIVE,
              doc="for a body pose or twist, of the position only"),
    Parameter("max_jerk", PER_DOF, JERK, valid=POSITIVE,
              doc="for a body pose or twist, of the position only; default: not limited"),
    Parameter("target_velocity", PER_DOF, VELOCITY, spaces=(JOINT_SPACE,),
              doc="velocity on reaching the target; default: at rest"),
    Parameter("max_angular_velocity", SCALAR, ANGULAR_VELOCITY, valid=POSITIVE,
              spaces=ROTATION_SPACES, doc="of the rotation; default 1 rad/s"),
    Parameter("max_angular_acceleration", SCALAR, ANGULAR_ACCELERATION, valid=POSITIVE,
              spaces=ROTATION_SPACES, doc="of the rotation; default 2 rad/s^2"),
    Parameter("max_angular_jerk", SCALAR, ANGULAR_JERK, valid=POSITIVE,
              spaces=ROTATION_SPACES, doc="of the rotation; default: not limited"),
), doc="online trajectory generation (ruckig), time-optimal under the limits; a linear "
       "limit never bounds a rotation", bounded=(("target_velocity", "max_velocity"),)))
for _name in ("linear", "cubic", "quintic"):
    INTERPOLATORS.register(Kind(_name, (Parameter("duration", SCALAR, TIME, required=True,
                                                          valid=POSITIVE),),
                                doc=f"{_name} interpolation over a fixed duration"))
INTERPOLATORS.register(Kind("none", (), doc="the reference jumps to the target"))

FEEDBACKS.register(Kind("proportional", (
    Parameter("gain", PER_AXIS, default=1.0, valid=NON_NEGATIVE,
              doc="[1/s], one number or one per dof / per axis"),),
    doc="velocity = gain * error"))
FEEDBACKS.register(Kind("pid", (
    Parameter("kp", PER_AXIS, default=1.0, valid=NON_NEGATIVE, doc="[1/s]"),
    Parameter("ki", PER_AXIS, default=0.0, valid=NON_NEGATIVE, doc="[1/s^2]"),
    Parameter("kd", PER_AXIS, default=0.0, valid=NON_NEGATIVE, doc="[-]")),
    doc="proportional, integral, derivative; each one number or one per dof / per axis"))

TOLERANCES: Registry[Kind] = Registry("tolerance")
TOLERANCES.register(Kind("pose", (
    Parameter("position", SCALAR, LENGTH, valid=POSITIVE, doc="default 1 mm"),
    Parameter("orientation", SCALAR, ANGLE, valid=POSITIVE, doc="default 1 deg")),
    space=POSE_SPACE, doc="the two parts of a body_pose task's tolerance"))
TOLERANCES.register(Kind("twist", (
    Parameter("linear", SCALAR, LINEAR_VELOCITY, valid=POSITIVE, doc="default 1 mm/s"),
    Parameter("angular", SCALAR, ANGULAR_VELOCITY, valid=POSITIVE, doc="default 1 deg/s")),
    space=TWIST_SPACE, doc="the two parts of a body_velocity task's tolerance"))
"""A tolerance of two parts, ``pose(position = 2 mm, orientation = 1 deg)``: each part
given alone may also be written as one number of its dimension."""

AXES_PARAMETERS = frozenset(p.name for registry in (TASKS, CONSTRAINTS)
                            for kind in map(registry.get, registry.names())
                            for p in kind.parameters if p.kind == AXES)
"""The names of the parameters that list the world's axes: their values are names, not
constants to substitute."""
