"""Forward kinematics of a world, computed once per state and shared by its readers.

A :class:`Kinematics` owns the ``pin.Data`` of a world's model. ``update(q)`` runs one
forward-kinematics and joint-Jacobians pass for a new state; frame poses and Jacobians
are read from it on first request and cached until the next state, so every task and
constraint of a cycle shares that pass. The runtime can share the object with the controller
(``Controller(..., kinematics=...)``) to read distances from the same pass.

Bodies attached at run time: :meth:`Kinematics.attach` re-places a fixed frame (and
the frames fixed to it) on another body's joint, keeping its current pose;
:meth:`Kinematics.place` gives the placement explicitly and :meth:`Kinematics.detach`
re-fixes it to the world. These edit the frames of the world's ``pin.Model`` in place,
so every reader of that model sees the change.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from .exceptions import InvalidParameter, UnknownName

_LOCAL_WORLD_ALIGNED = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
_WORLD = pin.ReferenceFrame.WORLD


class Kinematics:
    """Poses and Jacobians of a world's bodies at the latest state.

    Args:
        world: The world; only its ``model`` and body names are used.
    """

    def __init__(self, world):
        self.world = world
        self.model: pin.Model = world.model
        self.data: pin.Data = self.model.createData()
        self.q: np.ndarray | None = None
        self._key = b""
        self.stamp = 0
        self.placements = 0
        """How many times :meth:`place` has changed the model's frames."""
        self._poses: dict[int, pin.SE3] = {}
        self._jacobians: dict[int, np.ndarray] = {}
        self._frame_ids: dict[str, int] = {}
        self.supports, self.fold = _supports(self.model)

    def update(self, q: np.ndarray) -> bool:
        """Make ``q`` (nq float array) the current state; ``False`` if it already was."""
        key = q.tobytes()
        if key == self._key:
            return False
        self._key = key
        self.q = np.array(q, dtype=float)
        self.stamp += 1
        self._poses = {}
        self._jacobians = {}
        pin.computeJointJacobians(self.model, self.data, self.q)
        return True

    def frame_id(self, body: str) -> int:
        """Pinocchio frame id of ``body``; raises :class:`UnknownName` if absent."""
        frame = self._frame_ids.get(body)
        if frame is None:
            if not self.world.has_body(body):
                raise UnknownName("body", body, self.world.body_names())
            frame = self._frame_ids[body] = self.world.body_frame_id(body)
        return frame

    def pose(self, frame_id: int) -> pin.SE3:
        """Pose of a frame in the world at the current state (cached, do not modify)."""
        pose = self._poses.get(frame_id)
        if pose is None:
            pose = pin.updateFramePlacement(self.model, self.data, frame_id)
            self._poses[frame_id] = pose
        return pose

    def poses(self) -> dict[int, pin.SE3]:
        """The world poses computed so far at the current state, by frame id: a new
        mapping per state, so one kept for later keeps that state's poses (do not
        modify)."""
        return self._poses

    def jacobian(self, frame_id: int) -> np.ndarray:
        """6 x nv ``LOCAL_WORLD_ALIGNED`` Jacobian of a frame (cached, do not modify)."""
        jacobian = self._jacobians.get(frame_id)
        if jacobian is None:
            jacobian = pin.getFrameJacobian(self.model, self.data, frame_id,
                                            _LOCAL_WORLD_ALIGNED).reshape(6, -1)
            self._jacobians[frame_id] = jacobian        # 6 x 1 comes back flat
        return jacobian

    @property
    def joint_columns(self) -> np.ndarray:
        """6 x nvExtended: the ``WORLD`` Jacobian column of every joint coordinate at the
        current state, ``[v0; w]`` with ``v0`` the velocity of the moving body's point at
        the world's origin (a view of pinocchio's ``data.J``, which every state updates in
        place; do not modify). The Jacobian of joint ``j``'s body is
        ``(joint_columns * supports[j]) @ fold``."""
        return self.data.J

    def is_fixed(self, frame_id: int) -> bool:
        """Whether the frame is fixed to the world (no joint moves it)."""
        return self.model.frames[frame_id].parentJoint == 0

    def body_pose(self, body: str) -> pin.SE3:
        """Pose of ``body`` in the world at the current state (a copy)."""
        return self.pose(self.frame_id(body)).copy()

    def distance(self, body_a: str, body_b: str) -> float:
        """Distance [m] between the origins of two bodies at the current state."""
        a = self.pose(self.frame_id(body_a)).translation
        b = self.pose(self.frame_id(body_b)).translation
        return float(np.linalg.norm(a - b))

    def attach(self, body: str, parent: str) -> None:
        """Fix ``body`` to ``parent`` where it is now (needs a current state)."""
        if self.q is None:
            raise InvalidParameter("kinematics", "state", None, "update(q) before attach")
        body_id, parent_id = self.frame_id(body), self.frame_id(parent)
        placement = self.pose(parent_id).actInv(self.pose(body_id))
        self.place(body, parent, placement)

    def detach(self, body: str) -> None:
        """Fix ``body`` to the world where it is now (needs a current state)."""
        if self.q is None:
            raise InvalidParameter("kinematics", "state", None, "update(q) before detach")
        self.place(body, "world", self.pose(self.frame_id(body)).copy())

    def place(self, body: str, parent: str, placement: pin.SE3) -> None:
        """Fix ``body`` to ``parent`` at ``placement`` (body pose in the parent frame).

        Frames fixed to ``body`` (its sub-frames) move with it.
        """
        body_id, parent_id = self.frame_id(body), self.frame_id(parent)
        frames = self.model.frames
        if parent_id == body_id or parent_id in self._subtree(body_id):
            raise InvalidParameter("kinematics", "parent", parent,
                                   f"a body that is not '{body}' nor fixed to it")
        old_joint = frames[body_id].parentJoint
        old_inverse = frames[body_id].placement.inverse()
        parent_frame = frames[parent_id]
        new_placement = parent_frame.placement * placement
        for frame_id in self._subtree(body_id):
            frame = frames[frame_id]
            if frame.parentJoint == old_joint:
                frame.placement = new_placement * old_inverse * frame.placement
                frame.parentJoint = parent_frame.parentJoint
        frames[body_id].placement = new_placement
        frames[body_id].parentJoint = parent_frame.parentJoint
        frames[body_id].parentFrame = parent_id
        self.placements += 1
        self.stamp += 1             # same joints, frames moved: poses are computed again
        self._poses = {}
        self._jacobians = {}

    def _subtree(self, frame_id: int) -> list[int]:
        frames = self.model.frames
        found, stack = [], [frame_id]
        while stack:
            current = stack.pop()
            for child in range(len(frames)):
                if child != current and frames[child].parentFrame == current:
                    found.append(child)
                    stack.append(child)
        return found

    def __repr__(self) -> str:
        return (f"Kinematics(nq={self.model.nq}, frames={len(self.model.frames)}, "
                f"stamp={self.stamp})")


def _supports(model: pin.Model) -> tuple[np.ndarray, np.ndarray]:
    """Which joint coordinates move each joint's body (njoints x nvExtended, 0 or 1),
    and the map from those coordinates to velocity columns (nvExtended x nv: a mimic
    joint's coordinate onto its primary's column; the scaling is in the columns)."""
    extended = model.nvExtended
    supports = np.zeros((model.njoints, extended))
    fold = np.zeros((extended, model.nv))
    for joint in range(1, model.njoints):
        start, width = model.idx_vExtendeds[joint], model.nvExtendeds[joint]
        supports[joint] = supports[model.parents[joint]]
        supports[joint, start:start + width] = 1.0
        column = model.joints[joint].idx_v
        fold[start:start + width, column:column + width] = np.eye(width)
    return supports, fold
