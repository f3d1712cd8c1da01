"""The joint space of a joint group: its positions as angles, one per dof.

A group's configuration coordinates (``q[group.q_indices]``) are not always angles: a
continuous joint has two (cos, sin), a floating base seven (position, quaternion).
:class:`JointSpace` chains the group's pinocchio joint models, in the group's order,
into a model of its own, whose configuration is exactly the group's coordinates and
whose tangent space is its velocity coordinates. Positions as users see them
(targets, initial postures, logs) are the tangent vector from the neutral
configuration: the joint value for revolute and prismatic joints, the angle in
(-pi, pi] for continuous joints.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin


class JointSpace:
    """Positions, configurations and differences of a joint group.

    Args:
        model: The world's pinocchio model.
        joints: The group's joints with dofs of their own, in the group's order.

    Attributes:
        model: The chain of the group's joint models (``nq``: the group's coordinates,
            ``nv``: its dofs).
        continuous: Per dof, whether it belongs to a continuous joint (no position
            limit; positions equal modulo a turn).
    """

    def __init__(self, model: pin.Model, joints: tuple):
        chain = pin.Model()
        parent = 0
        for name in joints:
            joint = model.joints[model.getJointId(name)]
            parent = chain.addJoint(parent, joint, pin.SE3.Identity(), name)
        self.model = chain
        self.neutral = pin.neutral(chain)
        nqs, nvs = np.asarray(chain.nqs[1:]), np.asarray(chain.nvs[1:])
        self.continuous = np.repeat((nqs == 2) & (nvs == 1), nvs)

    def __repr__(self) -> str:
        return f"JointSpace(nq={self.model.nq}, nv={self.model.nv})"

    def positions(self, coordinates: np.ndarray) -> np.ndarray:
        """The group's positions [rad or m], one per dof, from its coordinates (nq)."""
        return pin.difference(self.model, self.neutral, coordinates)

    def coordinates(self, positions: np.ndarray) -> np.ndarray:
        """The group's coordinates (nq) at ``positions`` [rad or m], one per dof."""
        return pin.integrate(self.model, self.neutral, np.asarray(positions, dtype=float))

    def difference(self, start: np.ndarray, end: np.ndarray) -> np.ndarray:
        """The motion [rad or m] from positions ``start`` to ``end``, one per dof; a
        continuous joint turns the shortest way round (within [-pi, pi])."""
        return pin.difference(self.model, self.coordinates(start), self.coordinates(end))

    def nearest(self, anchor: np.ndarray, positions: np.ndarray) -> np.ndarray:
        """``positions`` with each continuous joint's angle moved by whole turns to
        the value nearest ``anchor``: where the shortest way from ``anchor`` ends."""
        positions = np.asarray(positions, dtype=float)
        return np.where(self.continuous, anchor + self.difference(anchor, positions),
                        positions)
