"""The joint servo of the MuJoCo driver: how a velocity command moves a simulated joint.

Each joint follows a position target integrated from its velocity command ``u``
[rad/s or m/s], with velocity feedback and gravity compensation::

    target' = u
    force   = kp (target - q) + kv (u - q') + g(q)

``kp`` [N m/rad or N/m] and ``kv`` [N m s/rad or N s/m] are the driver's ``gains``;
``g(q)`` is the gravity torque of the robot's links (routed through the joint's
actuator). The force is limited to the URDF's ``effort`` when it gives one.

A blocked joint (a finger on a part, an arm on the table) must neither wind up nor
crush, and a joint let go (a finger whose part slipped out) must not snap: at the
start of every control period the target is brought back within ::

    window = min(effort, kv v_max) / kp

of the measured position, and within the joint's range. ``effort`` and ``v_max`` are
the URDF's limits (``DEFAULT_WINDOW`` when it gives neither). Within a period of
length ``T`` the target moves by at most ``|u| T`` and the joint by ``|dq|``, so at
any time ``|target - q| <= window + |u| T + |dq|``. A blocked joint does not move
(``dq = 0``, ``q' = 0``): the servo pushes it with at most
``min(effort, kv v_max) + (kp T + kv) |u|``, and never more than ``effort``, where
MuJoCo clips the joint's actuator force. A joint let go settles at the speed where
damping balances the spring, ``kp window / kv <= v_max``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

DEFAULT_KP = 2000.0
"""[N m/rad or N/m]"""
DEFAULT_KV = 100.0
"""[N m s/rad or N s/m]"""
DEFAULT_WINDOW = 0.1
"""Largest distance [rad or m] between a joint's target and its measured position,
when the URDF gives the joint no effort limit."""


@dataclass(frozen=True)
class Servo:
    """The gains of every servoed joint: ``kp`` and ``kv`` by joint name, and the
    gains of the joints not named (those outside the driven group)."""

    kp: dict
    kv: dict
    default_kp: float = DEFAULT_KP
    default_kv: float = DEFAULT_KV

    @classmethod
    def default(cls, world) -> "Servo":
        return cls({}, {})

    @classmethod
    def from_options(cls, world, options: dict) -> "Servo":
        """The servo of a ``mujoco`` driver processor's checked ``options``: its
        ``gains``, one value or one per joint of its ``joint_group``.

        Raises:
            ValueError: a list of gains whose length is not the group's joints'.
        """
        gains = options.get("gains", {"kp": DEFAULT_KP, "kv": DEFAULT_KV})
        joints = world.joint_group(options["joint_group"]).joints
        return cls.from_gains(joints, gains.get("kp", DEFAULT_KP), gains.get("kv", DEFAULT_KV))

    @classmethod
    def from_gains(cls, joints: tuple, kp, kv) -> "Servo":
        """Gains given as scalars (every joint) or as one value per joint of ``joints``.

        Raises:
            ValueError: a list whose length is not the number of joints.
        """
        per_joint = {}
        for name, value in (("kp", kp), ("kv", kv)):
            values = [value] * len(joints) if not isinstance(value, (list, tuple)) else value
            if len(values) != len(joints):
                raise ValueError(f"gains: '{name}' has {len(values)} values, the driven "
                                 f"group has {len(joints)} joints")
            per_joint[name] = dict(zip(joints, (float(v) for v in values)))
        scalar = (lambda value, default: default if isinstance(value, (list, tuple))
                  else float(value))
        return cls(per_joint["kp"], per_joint["kv"], scalar(kp, DEFAULT_KP),
                   scalar(kv, DEFAULT_KV))

    def gains(self, joint: str) -> tuple[float, float]:
        """``(kp, kv)`` of ``joint``."""
        return self.kp.get(joint, self.default_kp), self.kv.get(joint, self.default_kv)

    def window(self, joint: str, effort: float, max_velocity: float) -> float:
        """How far [rad or m] the target of ``joint`` may lead its measured position,
        given its URDF ``effort`` [N m or N] and ``max_velocity`` [rad/s or m/s] (0 or
        infinite: none)."""
        kp, kv = self.gains(joint)
        forces = [force for force in (effort, kv * max_velocity)
                  if force > 0 and math.isfinite(force)]
        return min(forces) / kp if forces else DEFAULT_WINDOW
