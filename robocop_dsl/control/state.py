"""The state a controller cycle works on: kinematics restricted to the controlled joints."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from .exceptions import JointGroupOutsideController, UnknownName
from .kinematics import Kinematics
from .spatial import relative_jacobian


def resolve_group(world, name: str):
    """The joint group (or single joint seen as a group) ``name`` of ``world``."""
    if not world.has_group(name) and name not in world.joint_names():
        raise UnknownName("joint group", name, world.group_names() + world.joint_names())
    return world.joint_group(name)


class ControlState:
    """What tasks and constraints read during a cycle.

    Jacobians returned here have one column per controlled joint (the controller's
    group, in its order); so have ``group_positions``, the joints' positions as
    angles (or lengths), one per dof, whatever the joint type. ``velocity`` is the current joint-velocity estimate of the
    group [rad/s or m/s]: the measured one when the runtime passes it, else the
    previous command.

    Args:
        kinematics: The world's kinematics.
        group: The controlled joint group.
        time_step: The control period [s].
    """

    def __init__(self, kinematics: Kinematics, group, time_step: float):
        self.kinematics = kinematics
        self.world = kinematics.world
        self.group = group
        self.time_step = time_step
        self.dofs = group.dofs
        self.v_indices = np.asarray(group.v_indices, dtype=int)
        self.q_indices = np.asarray(group.q_indices, dtype=int)
        self.columns = _as_slice(self.v_indices)
        """The controlled columns of a model-wide (nv) Jacobian: a slice when they follow
        one another."""
        self.velocity = np.zeros(self.dofs)
        self.previous_command = np.zeros(self.dofs)
        self.max_acceleration = np.array(group.max_acceleration, dtype=float)
        """Acceleration limits of the controlled joints [rad/s^2 or m/s^2]: the world's
        met with the enabled ``joint_kinematic`` constraints' (set by the controller)."""
        self.revision = 0
        """Bumped whenever the QP's structure may change (enabling, priorities...)."""
        self.sensors = None
        """Where force tasks read the wrench a body exerts on the environment: an
        object with ``wrench(body) -> [fx, fy, fz, tx, ty, tz]`` [N, N m] (world frame),
        updated before each cycle; ``None`` when nothing measures forces."""
        self.collision_watch = None
        """The pairs of the controller's ``collision_avoidance`` constraints
        (:mod:`~robocop_dsl.control.constraints.collision_watch`), made by the first."""
        self._jacobians: dict[tuple[int, int], np.ndarray] = {}
        self._stamp = -1
        self._positions = np.zeros(self.dofs)
        self._positions_stamp = -1

    @property
    def q(self) -> np.ndarray:
        """Configuration (nq) of the whole model at this cycle."""
        return self.kinematics.q

    @property
    def group_positions(self) -> np.ndarray:
        """Positions of the controlled joints [rad or m], one per dof (a continuous
        joint's angle in (-pi, pi]); computed once per state, do not modify."""
        kinematics = self.kinematics
        if self._positions_stamp != kinematics.stamp:
            self._positions = self.group.space.positions(kinematics.q[self.q_indices])
            self._positions_stamp = kinematics.stamp
        return self._positions

    def body(self, name: str) -> int:
        """Frame id of a body; raises :class:`UnknownName` listing the bodies."""
        return self.kinematics.frame_id(name)

    def group_columns(self, name: str) -> tuple[object, np.ndarray]:
        """A joint group of the world and the columns of its joints in the command."""
        group = resolve_group(self.world, name)
        position = {int(v): i for i, v in enumerate(self.v_indices)}
        outside = [joint for joint, v in zip(group.joints, group.v_indices)
                   if int(v) not in position]
        if outside:
            raise JointGroupOutsideController(name, outside, self.group.name)
        return group, np.array([position[int(v)] for v in group.v_indices], dtype=int)

    def pose(self, frame_id: int, reference_id: int = 0) -> pin.SE3:
        """Pose of a frame in a reference frame (``0`` is the world)."""
        pose = self.kinematics.pose(frame_id)
        if reference_id == 0:
            return pose
        return self.kinematics.pose(reference_id).actInv(pose)

    def jacobian(self, frame_id: int, reference_id: int = 0) -> np.ndarray:
        """6 x dofs Jacobian of ``[v, w]`` of a frame relative to a reference, in its axes."""
        if self._stamp != self.kinematics.stamp:
            self._jacobians.clear()
            self._stamp = self.kinematics.stamp
        key = (frame_id, reference_id)
        jacobian = self._jacobians.get(key)
        if jacobian is None:
            kinematics = self.kinematics
            jacobian = kinematics.jacobian(frame_id)[:, self.columns]
            if reference_id != 0:
                reference_pose = kinematics.pose(reference_id)
                if kinematics.is_fixed(reference_id):
                    rotation_t = reference_pose.rotation.T
                    jacobian = np.vstack((rotation_t @ jacobian[:3], rotation_t @ jacobian[3:]))
                else:
                    reference = kinematics.jacobian(reference_id)[:, self.columns]
                    jacobian = relative_jacobian(jacobian, kinematics.pose(frame_id),
                                                 reference, reference_pose)
            self._jacobians[key] = jacobian
        return jacobian

    def __getstate__(self) -> dict:
        """Pickled without its :attr:`sensors` (they read the run's driver) and its
        :attr:`collision_watch` (coal's objects): the state of a task's copy that only
        reads names and poses (:meth:`Task.detached <robocop_dsl.control.Task.detached>`)."""
        return {**self.__dict__, "sensors": None, "collision_watch": None}

    def __repr__(self) -> str:
        return f"ControlState(group={self.group.name!r}, dofs={self.dofs}, dt={self.time_step})"


def _as_slice(indices: np.ndarray):
    """``indices`` as a slice when they are consecutive (views instead of copies)."""
    if len(indices) == 0:
        return indices
    first = int(indices[0])
    if np.array_equal(indices, np.arange(first, first + len(indices))):
        return slice(first, first + len(indices))
    return indices
