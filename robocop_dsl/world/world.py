"""The :class:`World`: names, limits and groups of a composed world, and its pinocchio
model (built on first use, so that checking a mission never pays for it)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..diagnostics import Diagnostic, DiagnosticError
from . import paths
from .assembly import Assembly, BodyInfo, assemble
from .description import WorldDescription, read_description
from .processors import Names, check_processors
from .urdf import JointInfo

if TYPE_CHECKING:
    from .joint_space import JointSpace


@dataclass(frozen=True)
class JointGroup:
    """An ordered set of joints and their stacked coordinates.

    Limits are per velocity dof, SI (rad, m, rad/s, m/s); ``inf`` where unlimited
    (continuous joints have no position limit). ``q_indices``/``v_indices`` locate the
    group's coordinates in the world's ``q`` (size ``model.nq``) and ``v`` (size
    ``model.nv``); ``space`` turns coordinates into positions, one per dof, and back.
    """

    name: str
    joints: tuple
    dofs: int
    lower: np.ndarray
    upper: np.ndarray
    max_velocity: np.ndarray
    max_acceleration: np.ndarray
    q_indices: np.ndarray
    v_indices: np.ndarray
    space: JointSpace | None = None

    def positions(self, q: np.ndarray) -> np.ndarray:
        """The group's positions [rad or m], one per dof, in the world's ``q``."""
        return self.space.positions(q[self.q_indices])


class World:
    """A composed world: bodies, joints, joint groups, processors and the kinematic model."""

    def __init__(self, path: Path, assembly: Assembly, processors: dict):
        self.path = Path(path)
        self._assembly = assembly
        self.processors = processors
        self.urdf = assembly.urdf

    def __repr__(self) -> str:
        return (f"World({self.path.name}: {len(self._assembly.bodies)} bodies, "
                f"{len(self._assembly.joints)} joints, {len(self._assembly.groups)} groups)")

    def body_names(self) -> list:
        return list(self._assembly.bodies)

    def has_body(self, name: str) -> bool:
        return name in self._assembly.bodies

    def body(self, name: str) -> BodyInfo:
        return self._assembly.bodies[name]

    def joint_names(self) -> list:
        return list(self._assembly.joints)

    def joint(self, name: str) -> JointInfo:
        return self._assembly.joints[name]

    def group_names(self) -> list:
        return list(self._assembly.groups)

    def has_group(self, name: str) -> bool:
        return name in self._assembly.groups

    @property
    def allowed_collisions(self) -> set:
        """Pairs of bodies (frozensets of names) never checked for collisions: the models'
        SRDF ``disable_collisions`` and the world's ``allowed_collisions:``."""
        return self._assembly.allowed_collisions

    @property
    def physics(self):
        """The world's ``physics:`` (:class:`~.description.Physics`)."""
        return self._assembly.physics

    def free_bodies(self) -> list:
        """The root bodies of the ``free: true`` models, each on a floating joint."""
        return list(self._assembly.free)

    def free_model(self, body: str):
        """The ``free: true`` model entry whose root is ``body``
        (:class:`~.description.ModelEntry`)."""
        return self._assembly.free[body]

    def place_free(self, q: np.ndarray, body: str, pose) -> None:
        """Put free ``body`` at ``pose`` (``pin.SE3`` or 4x4, world frame) in the
        configuration ``q`` (its floating joint's coordinates, in place)."""
        import pinocchio as pin

        model = self.model
        joint = model.frames[self.body_frame_id(body)].parentJoint
        start = model.joints[joint].idx_q
        pose = pose if isinstance(pose, pin.SE3) else pin.SE3(np.asarray(pose, dtype=float))
        q[start:start + 7] = pin.SE3ToXYZQUAT(model.jointPlacements[joint].actInv(pose))

    def link_source(self, body: str) -> tuple:
        """``(URDF path, line)`` of the ``<link>`` of ``body``; ``None`` for a body no
        URDF wrote (``world``)."""
        return self._assembly.links.get(body)

    def force_sensors(self) -> dict:
        """The ``force_sensor`` processors by the body each measures."""
        return {p.options["body"]: p for p in self.processors.values()
                if p.type == "force_sensor"}

    def controller_names(self) -> list:
        return [p.name for p in self.processors.values() if p.type == "qp_controller"]

    def moving_joints(self, name: str) -> tuple[JointInfo, ...]:
        """The joints with dofs of the group ``name`` in its order, or of the single joint
        ``name``: what :meth:`joint_group` stacks, read without the pinocchio model."""
        if name in self._assembly.groups:
            joints = self._assembly.groups[name].joints
        elif name in self._assembly.joints:
            joints = (name,)
        else:
            raise KeyError(name)
        return tuple(self._assembly.joints[j] for j in joints if self._assembly.joints[j].dofs)

    def joint_group(self, name: str) -> JointGroup:
        """The group ``name``, or a single joint seen as a group."""
        from .joint_space import JointSpace

        infos = self.moving_joints(name)
        stack = (lambda attr: np.concatenate([getattr(i, attr) for i in infos])
                 if infos else np.zeros(0))
        dofs = sum(i.dofs for i in infos)
        names = tuple(i.name for i in infos)
        q_idx, v_idx = self._indices(names)
        return JointGroup(name, names, dofs, stack("lower"), stack("upper"),
                          stack("max_velocity"), np.full(dofs, math.inf), q_idx, v_idx,
                          JointSpace(self.model, names))

    def _indices(self, joints: tuple) -> tuple:
        if not joints:
            return np.zeros(0, dtype=int), np.zeros(0, dtype=int)
        model = self.model
        q_idx, v_idx = [], []
        for name in joints:
            joint = model.joints[model.getJointId(name)]
            q_idx.extend(range(joint.idx_q, joint.idx_q + joint.nq))
            v_idx.extend(range(joint.idx_v, joint.idx_v + joint.nv))
        return np.array(q_idx, dtype=int), np.array(v_idx, dtype=int)

    def copy(self) -> "World":
        """A world sharing this one's description but owning a copy of the model, so
        that moving or attaching bodies in one never affects the other."""
        import pinocchio as pin

        twin = World(self.path, self._assembly, self.processors)
        twin.model = pin.Model(self.model)
        return twin

    @cached_property
    def model(self):
        """The pinocchio model of the whole world (mimic joints kept as mimics)."""
        import pinocchio as pin

        return pin.buildModelFromXML(self.urdf, True)

    @cached_property
    def visual_model(self):
        import pinocchio as pin

        return pin.buildGeomFromUrdfString(self.model, self.urdf, pin.GeometryType.VISUAL)

    @cached_property
    def collision_model(self):
        import pinocchio as pin

        return pin.buildGeomFromUrdfString(self.model, self.urdf, pin.GeometryType.COLLISION)

    def body_frame_id(self, name: str) -> int:
        import pinocchio as pin

        if name not in self._assembly.bodies:
            raise KeyError(name)
        return self.model.getFrameId(name, pin.FrameType.BODY)

    def neutral_configuration(self) -> np.ndarray:
        import pinocchio as pin

        return pin.neutral(self.model)

    def initial_position(self, joint: str) -> np.ndarray:
        """Where the world starts ``joint``: its ``initial:`` posture, one value per dof
        [rad or m], zeros when it has none (the neutral configuration, for a revolute or
        prismatic joint: what :meth:`initial_configuration` holds, read without the
        pinocchio model)."""
        return np.asarray(self._assembly.initial.get(joint, np.zeros(self.joint(joint).dofs)),
                          dtype=float)

    def initial_configuration(self) -> np.ndarray:
        """The neutral configuration with the world's ``initial:`` postures applied:
        each posture is a joint's positions, one per dof (an angle for a continuous
        joint, a motion from the origin for a floating one)."""
        import pinocchio as pin

        model = self.model
        motion = np.zeros(model.nv)
        for name, values in self._assembly.initial.items():
            joint = model.joints[model.getJointId(name)]
            motion[joint.idx_v:joint.idx_v + joint.nv] = values
        return pin.integrate(model, self.neutral_configuration(), motion)

    def body_pose(self, name: str, q: np.ndarray):
        """Pose of body ``name`` in the world frame at configuration ``q`` (``pin.SE3``)."""
        import pinocchio as pin

        data = self.model.createData()
        pin.forwardKinematics(self.model, data, q)
        return pin.SE3(pin.updateFramePlacement(self.model, data, self.body_frame_id(name)))

    def body_placements(self, q: np.ndarray) -> dict:
        """World pose (``pin.SE3``) of every body at configuration ``q``, by name."""
        import pinocchio as pin

        data = self.model.createData()
        pin.framesForwardKinematics(self.model, data, q)
        return {name: pin.SE3(data.oMf[self.body_frame_id(name)])
                for name in self._assembly.bodies}

    def body_jacobian(self, name: str, q: np.ndarray) -> np.ndarray:
        """6 x nv Jacobian of body ``name`` (linear then angular, LOCAL_WORLD_ALIGNED)."""
        import pinocchio as pin

        data = self.model.createData()
        return pin.computeFrameJacobian(self.model, data, q, self.body_frame_id(name),
                                        pin.ReferenceFrame.LOCAL_WORLD_ALIGNED).reshape(6, -1)


def load_world(path: str | Path, relative_to: Path | None = None) -> World:
    """Load a world file (a path, or a name along the robots path).

    Raises:
        DiagnosticError: every problem found, each naming its file and line.
    """
    resolved = paths.resolve_world_path(path, relative_to)
    if resolved is None:
        folders = ", ".join(str(p) for p in paths.search_folders(relative_to))
        raise DiagnosticError([Diagnostic(
            "world-not-found", f"cannot find world file '{path}'", str(path), None,
            hint=f"looked in: {folders} (add folders with ROBOCOP_PATH)")])
    description = read_description(resolved)
    return World(resolved, *_assemble(description))


def _assemble(description: WorldDescription) -> tuple:
    """The world's assembly and checked processors.

    Raises:
        DiagnosticError: the problems of both.
    """
    try:
        assembly = assemble(description)
    except DiagnosticError as error:
        _, problems = check_processors(description.processors, None)
        raise DiagnosticError(error.diagnostics + problems) from None
    names = Names({n: g.joints for n, g in assembly.groups.items()}, set(assembly.joints),
                  {j for j, info in assembly.joints.items() if info.dofs},
                  list(assembly.bodies))
    processors, problems = check_processors(description.processors, names)
    if problems:
        raise DiagnosticError(problems)
    return assembly, processors
