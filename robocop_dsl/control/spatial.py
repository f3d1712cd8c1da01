"""Spatial helpers: pose errors, relative Jacobians, targets and interpolation charts.

Conventions used by every body task and constraint:

- A pose ``T`` of a body "in a reference frame" maps body coordinates to reference
  coordinates (``T_ref_body = T_world_ref^-1 T_world_body``).
- A body velocity is a 6-vector ``[v, w]``: ``v`` the linear velocity of the body's
  origin and ``w`` its angular velocity, both expressed in the reference frame's
  axes (pinocchio's ``LOCAL_WORLD_ALIGNED`` when the reference is ``world``).
- The pose error towards a target ``T*`` is the SE(3) logarithm of ``T^-1 T*`` (the
  body-frame twist that reaches ``T*`` in unit time) rotated into the reference axes,
  so that commanding ``gain * error`` as the body velocity converges to ``T*``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin


class Current:
    """The target ``current``: hold the value the task has when it (re)starts."""

    def __repr__(self) -> str:
        return "CURRENT"


CURRENT = Current()


@dataclass(frozen=True)
class BodyTarget:
    """A target that tracks another body's pose, read from the same state every cycle.

    Attributes:
        body: The tracked body.
        offset: ``None``, a 3-vector [m] added to the tracked position and expressed in
            the task's reference frame, or a ``pin.SE3`` composed on the right of the
            tracked pose (expressed in the tracked body's frame).
    """

    body: str
    offset: np.ndarray | pin.SE3 | None = None

    def apply(self, pose: pin.SE3) -> pin.SE3:
        """The tracked ``pose`` (in the reference frame) with the offset applied."""
        if self.offset is None:
            return pose
        if isinstance(self.offset, pin.SE3):
            return pose * self.offset
        return pin.SE3(pose.rotation, pose.translation + self.offset)

    def __repr__(self) -> str:
        if self.offset is None:
            return f"BodyTarget({self.body!r})"
        offset = self.offset if isinstance(self.offset, pin.SE3) else list(self.offset)
        return f"BodyTarget({self.body!r}, offset={offset})"


def same_target(first, second) -> bool:
    """Whether two task targets (vectors, rotations, ``pin.SE3``, :class:`BodyTarget`,
    ``CURRENT``) are equal; ``CURRENT`` never equals anything, being the value at the
    time it is set."""
    if isinstance(first, BodyTarget) and isinstance(second, BodyTarget):
        return first.body == second.body and _same_value(first.offset, second.offset)
    if isinstance(first, (BodyTarget, Current)) or isinstance(second, (BodyTarget, Current)):
        return False
    return _same_value(first, second)


def _same_value(first, second) -> bool:
    if first is None or second is None:
        return first is second
    if isinstance(first, pin.SE3) != isinstance(second, pin.SE3):
        return False
    first, second = (getattr(v, "homogeneous", v) for v in (first, second))
    return np.array_equal(np.asarray(first), np.asarray(second))


def skew(vector: np.ndarray) -> np.ndarray:
    """The 3x3 matrix of ``vector x .``."""
    x, y, z = np.asarray(vector, dtype=float).tolist()
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def rotation_error(target: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """Rotation vector [rad] from ``rotation`` to ``target``, in the reference axes."""
    return pin.log3(target @ rotation.T)


def pose_error(target: pin.SE3, pose: pin.SE3) -> np.ndarray:
    """SE(3) logarithm of ``pose^-1 target`` rotated into the reference axes [m, rad]."""
    twist = pin.log6(pose.actInv(target)).vector
    return twist.reshape(2, 3).dot(pose.rotation.T).reshape(6)


def relative_jacobian(jacobian: np.ndarray, pose: pin.SE3, reference_jacobian: np.ndarray,
                      reference_pose: pin.SE3) -> np.ndarray:
    """Jacobian of a body's velocity relative to a moving reference, in its axes.

    Args:
        jacobian: 6 x n ``LOCAL_WORLD_ALIGNED`` Jacobian of the body.
        pose: The body's pose in the world.
        reference_jacobian: 6 x n ``LOCAL_WORLD_ALIGNED`` Jacobian of the reference.
        reference_pose: The reference's pose in the world.

    Returns:
        6 x n Jacobian of ``[v, w]`` of the body relative to the reference.
    """
    offset = pose.translation - reference_pose.translation
    linear = jacobian[:3] - reference_jacobian[:3] + skew(offset) @ reference_jacobian[3:]
    angular = jacobian[3:] - reference_jacobian[3:]
    rotation_t = reference_pose.rotation.T
    return np.vstack((rotation_t @ linear, rotation_t @ angular))


def as_pose(value) -> pin.SE3 | None:
    """``value`` as a ``pin.SE3`` (from an SE3 or a 4x4 matrix), else ``None``."""
    if isinstance(value, pin.SE3):
        return value.copy()
    array = np.asarray(value, dtype=float) if not isinstance(value, str) else None
    if array is not None and array.shape == (4, 4):
        return pin.SE3(array[:3, :3].copy(), array[:3, 3].copy())
    return None


class VectorChart:
    """Identity chart: the task's values are already vectors."""

    def to_vector(self, value: np.ndarray) -> np.ndarray:
        return value

    def from_vector(self, vector: np.ndarray) -> np.ndarray:
        return vector

    def velocity(self, vector: np.ndarray, rate: np.ndarray) -> np.ndarray:
        """Task velocity at ``vector`` moving at ``rate``."""
        return rate

    def rate(self, velocity: np.ndarray) -> np.ndarray:
        """Chart rate at the anchor for a task velocity."""
        return velocity


class JointChart(VectorChart):
    """Joint positions where continuous joints wrap: a goal is read as the equivalent
    angle nearest the anchor (the start), so interpolating goes the shortest way round.

    Args:
        space: The group's :class:`~robocop_dsl.world.joint_space.JointSpace`.
        anchor: Positions [rad or m] the interpolation starts from.
    """

    def __init__(self, space, anchor: np.ndarray):
        self.space = space
        self.anchor = anchor

    def to_vector(self, value: np.ndarray) -> np.ndarray:
        return self.space.nearest(self.anchor, value)


class RotationChart:
    """Rotations as ``R = anchor exp(r)``: interpolating ``r`` follows geodesics."""

    def __init__(self, anchor: np.ndarray):
        self.anchor = anchor

    def to_vector(self, rotation: np.ndarray) -> np.ndarray:
        return pin.log3(self.anchor.T @ rotation)

    def from_vector(self, vector: np.ndarray) -> np.ndarray:
        return self.anchor @ pin.exp3(vector)

    def velocity(self, vector: np.ndarray, rate: np.ndarray) -> np.ndarray:
        return self.from_vector(vector) @ (pin.Jexp3(vector) @ rate)

    def rate(self, velocity: np.ndarray) -> np.ndarray:
        return self.anchor.T @ velocity


class PoseChart:
    """Poses as ``[p, r]``: position, and rotation ``anchor.rotation exp(r)``."""

    def __init__(self, anchor: pin.SE3):
        self.rotation = RotationChart(anchor.rotation.copy())

    def to_vector(self, pose: pin.SE3) -> np.ndarray:
        return np.concatenate((pose.translation, self.rotation.to_vector(pose.rotation)))

    def from_vector(self, vector: np.ndarray) -> pin.SE3:
        return pin.SE3(self.rotation.from_vector(vector[3:]), vector[:3].copy())

    def velocity(self, vector: np.ndarray, rate: np.ndarray) -> np.ndarray:
        return np.concatenate((rate[:3], self.rotation.velocity(vector[3:], rate[3:])))

    def rate(self, velocity: np.ndarray) -> np.ndarray:
        return np.concatenate((velocity[:3], self.rotation.rate(velocity[3:])))
