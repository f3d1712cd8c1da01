"""Constraints: bounds on the command that hold at every priority level."""

from __future__ import annotations

from .base import Constraint
from .body_velocity import BodyVelocityConstraint
from .collision_avoidance import CollisionAvoidanceConstraint
from .joint_kinematic import JointKinematicConstraint

CONSTRAINTS: dict[str, type[Constraint]] = {
    cls.kind: cls for cls in (JointKinematicConstraint, BodyVelocityConstraint,
                              CollisionAvoidanceConstraint)
}

__all__ = ["BodyVelocityConstraint", "CONSTRAINTS", "CollisionAvoidanceConstraint", "Constraint",
           "JointKinematicConstraint"]

