"""Where the bodies of a world are, as ``/tf`` and ``/tf_static`` give them: each body's
pose in the world frame, bodies fixed to the world once, the others for a batch of
configurations at once (the forward kinematics of the world's pinocchio model in numpy,
along its joints: a few array operations per joint for the whole batch, rather than a
call to pinocchio per configuration and a copy out per body)."""

from __future__ import annotations

import numpy as np

from ..world.description import ROOT


class BodyFrames:
    """The world poses of a world's bodies, computed from whole configurations.

    The kinematic model is copied when the object is made: a run re-parents the frames
    of the model it runs on (``attach``), so make it before the run. Bodies the run
    moves that way are not known here: their poses come with the records.

    Attributes:
        fixed: The bodies fixed to the world (``world`` itself left out).
        moving: The bodies carried by a joint (floating joints of free bodies included).
        fixed_poses: ``len(fixed) x 4 x 4`` world poses [m].
    """

    def __init__(self, world):
        model = world.model.copy()
        frames = {body: model.frames[world.body_frame_id(body)]
                  for body in world.body_names() if body != ROOT}
        self.fixed = [body for body, frame in frames.items() if frame.parentJoint == 0]
        self.moving = [body for body, frame in frames.items() if frame.parentJoint != 0]
        self.fixed_poses = np.array([frames[body].placement.homogeneous
                                     for body in self.fixed]).reshape(-1, 4, 4)
        self._joints = [_JointMotion(model, joint) for joint in range(1, model.njoints)]
        self._parents = [model.parents[joint] for joint in range(1, model.njoints)]
        self._body_joints = np.array([frames[body].parentJoint for body in self.moving],
                                     dtype=int)
        placements = np.array([frames[body].placement.homogeneous
                               for body in self.moving]).reshape(-1, 4, 4)
        self._body_rotations, self._body_offsets = placements[:, :3, :3], placements[:, :3, 3]

    def moving_poses(self, configurations: np.ndarray) -> np.ndarray:
        """``N x len(moving) x 4 x 4`` world poses [m] of the moving bodies at each of
        the ``N`` whole configurations (``N x nq``)."""
        configurations = np.asarray(configurations, dtype=float)
        count = len(configurations)
        rotations = np.empty((len(self._joints) + 1, count, 3, 3))
        positions = np.empty((len(self._joints) + 1, count, 3))
        rotations[0], positions[0] = np.eye(3), 0.0
        for index, joint in enumerate(self._joints, start=1):
            rotation, offset = joint.placed(configurations)
            parent = self._parents[index - 1]
            rotations[index] = rotations[parent] @ rotation
            positions[index] = (rotations[parent] @ offset[..., None])[..., 0] + positions[parent]
        rotations = rotations[self._body_joints].swapaxes(0, 1)
        poses = np.zeros((count, len(self.moving), 4, 4))
        poses[..., :3, :3] = rotations @ self._body_rotations
        poses[..., :3, 3] = ((rotations @ self._body_offsets[..., None])[..., 0]
                             + positions[self._body_joints].swapaxes(0, 1))
        poses[..., 3, 3] = 1.0
        return poses


class _JointMotion:
    """A joint's placement in its parent joint's frame for a batch of whole
    configurations: revolute and prismatic joints (one dof about or along a fixed axis,
    continuous joints included) and floating joints with numpy; any other joint (a
    mimic joint...) one configuration at a time with pinocchio."""

    def __init__(self, model, joint: int):
        self._model = model.joints[joint]
        self._data = self._model.createData()
        self._start = self._model.idx_q
        self._kind = self._model.shortname()
        placement = model.jointPlacements[joint]
        self._rotation, self._offset = placement.rotation.copy(), placement.translation.copy()
        self._axis = None
        if self._model.nv == 1 and self._model.nq in (1, 2) and "Mimic" not in self._kind:
            import pinocchio as pin

            self._model.calc(self._data, pin.neutral(model))
            screw = self._data.S
            screw = np.asarray(screw.matrix() if hasattr(screw, "matrix") else screw).ravel()
            if not (screw[:3].any() and screw[3:].any()):
                self._axis = screw
                angular = screw[3:]
                cross = np.array([[0, -angular[2], angular[1]], [angular[2], 0, -angular[0]],
                                  [-angular[1], angular[0], 0]])
                self._turns = (self._rotation @ cross, self._rotation @ cross @ cross)
                self._slide = self._rotation @ screw[:3]

    def placed(self, configurations: np.ndarray) -> tuple:
        """``(N x 3 x 3, N x 3)``: the joint frame's rotation and position [m] in its
        parent joint's frame at each configuration."""
        start = self._start
        if self._axis is not None:
            if self._model.nq == 2:         # continuous: cos and sin of the angle
                angle = np.arctan2(configurations[:, start + 1], configurations[:, start])
            else:
                angle = configurations[:, start]
            sine, cosine = np.sin(angle)[:, None, None], np.cos(angle)[:, None, None]
            rotation = self._rotation + sine * self._turns[0] + (1 - cosine) * self._turns[1]
            return rotation, self._offset + np.outer(angle, self._slide)
        if self._kind == "JointModelFreeFlyer":
            rotation = quaternion_matrices(configurations[:, start + 3:start + 7])
            offset = configurations[:, start:start + 3]
        else:
            motions = np.empty((len(configurations), 4, 4))
            for row, q in enumerate(configurations):
                self._model.calc(self._data, q)
                motions[row] = self._data.M.homogeneous
            rotation, offset = motions[:, :3, :3], motions[:, :3, 3]
        placed = (self._rotation @ offset[..., None])[..., 0] + self._offset
        return self._rotation @ rotation, placed


def quaternion_matrices(quaternions: np.ndarray) -> np.ndarray:
    """``N x 3 x 3`` rotations of the unit quaternions ``x, y, z, w`` (``N x 4``)."""
    x, y, z, w = (quaternions / np.linalg.norm(quaternions, axis=1, keepdims=True)).T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
        np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
        np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1)],
        -2)


def position_quaternion(poses: np.ndarray) -> np.ndarray:
    """``... x 7``: position [m] then unit quaternion ``x, y, z, w`` (``w >= 0``) of
    each ``4 x 4`` pose of ``poses`` (Shepperd's method, from the largest of the
    rotation's diagonal and trace)."""
    poses = np.asarray(poses, dtype=float)
    m = poses[..., :3, :3]
    m00, m01, m02 = m[..., 0, 0], m[..., 0, 1], m[..., 0, 2]
    m10, m11, m12 = m[..., 1, 0], m[..., 1, 1], m[..., 1, 2]
    m20, m21, m22 = m[..., 2, 0], m[..., 2, 1], m[..., 2, 2]
    trace = m00 + m11 + m22
    candidates = np.stack([            # x, y, z, w, each scaled by 4 times its pivot
        np.stack([1 + m00 - m11 - m22, m01 + m10, m02 + m20, m21 - m12], -1),
        np.stack([m01 + m10, 1 - m00 + m11 - m22, m12 + m21, m02 - m20], -1),
        np.stack([m02 + m20, m12 + m21, 1 - m00 - m11 + m22, m10 - m01], -1),
        np.stack([m21 - m12, m02 - m20, m10 - m01, 1 + trace], -1)], -2)
    pivot = np.stack([m00, m11, m22, trace], -1).argmax(-1)
    chosen = np.take_along_axis(candidates, pivot[..., None, None], -2)[..., 0, :]
    chosen /= np.linalg.norm(chosen, axis=-1, keepdims=True)
    chosen *= np.where(chosen[..., 3:] < 0, -1.0, 1.0)
    return np.concatenate([poses[..., :3, 3], chosen], -1)
