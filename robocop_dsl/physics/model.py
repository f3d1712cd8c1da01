"""The MuJoCo model of a world: a ``mujoco.MjSpec`` built from its assembled URDF.

Every URDF link is a MuJoCo body named like it, placed by its joint's origin; a
``revolute``/``continuous`` joint is a hinge, ``prismatic`` a slide, a ``free: true``
model's floating joint a free joint (its body a child of the world, where the world
places it). Inertias come from ``<inertial>``; a robot link without one gets the
inertia of its collision shapes at MuJoCo's default density (1000 kg/m^3), a free
model must give its mass. Contact geometry comes from ``<collision>`` (boxes,
cylinders, spheres, and meshes MuJoCo reads: STL, OBJ, MSH); ``<visual>`` is left
out. Pairs the world leaves out of collision checks (adjacent bodies, SRDF
``disable_collisions``, ``allowed_collisions:``) are left out of contact; a mimic
joint is held to its primary by a joint equality.

Each hinge and slide gets the joint servo of
:mod:`~robocop_dsl.physics.servo`; the robot's bodies are gravity-compensated through
their actuators. Each free body gets an inactive weld to every other body, which
``attach`` turns on.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..diagnostics import Diagnostic, DiagnosticError, SourceFile, Span
from ..world.description import ROOT
from .servo import Servo

MESH_FORMATS = (".stl", ".obj", ".msh")
"""Mesh files MuJoCo reads."""
CONTACT_TIME_CONSTANT = 0.01
"""[s] How fast a contact's penetration is undone (MuJoCo's ``solref``); at least twice
the physics step, which stability needs."""
CONTACT_IMPEDANCE = (0.95, 0.99, 0.001, 0.5, 2.0)
"""MuJoCo's ``solimp`` of every contact: stiffer than its default, so that a gripper's
squeeze sinks its fingers about a millimetre into a part, not a centimetre."""
WELD_TIME_CONSTANT = 0.005
"""[s] How fast a weld (``attach``) undoes a drift: at least twice the physics step."""
WELD_IMPEDANCE = (0.99, 0.999, 0.001, 0.5, 2.0)
"""MuJoCo's ``solimp`` of a weld: nearly rigid, a carried part stays put in the tool."""
MIN_MASS = 1e-5
"""Mass [kg] (and inertia [kg m^2]) given to a moving link that has none."""


@dataclass
class PhysicsModel:
    """A world's compiled MuJoCo model and how its names map to MuJoCo's ids.

    ``joints`` maps each hinge or slide to ``(qpos address, dof address)``; ``servoed``
    lists the joints with a servo, in actuator order (two actuators each: the position
    servo, then the velocity feedback); ``free`` maps each free body to its
    ``(qpos address, dof address, body id)``; ``welds`` maps ``(free body, body)`` to
    the weld equality's id.
    """

    spec: object
    model: object
    joints: dict = field(default_factory=dict)
    servoed: list = field(default_factory=list)
    free: dict = field(default_factory=dict)
    welds: dict = field(default_factory=dict)
    mimics: dict = field(default_factory=dict)
    limits: dict = field(default_factory=dict)
    """Each servoed joint's URDF ``(effort [N m or N], velocity [rad/s or m/s])`` limits
    (0: none)."""


def physics_model(world, time_step: float = 0.002, servo: Servo | None = None) -> PhysicsModel:
    """Build and compile the MuJoCo model of ``world``.

    Args:
        world: The loaded world.
        time_step: The physics step [s].
        servo: The joint servo; by default :class:`Servo` with its default gains.

    Raises:
        DiagnosticError: a link MuJoCo cannot simulate, located in its URDF.
    """
    import mujoco

    builder = _Builder(world, servo or Servo.default(world), mujoco)
    spec = builder.build(time_step)
    if builder.problems:
        raise DiagnosticError(builder.problems)
    try:
        model = spec.compile()
    except ValueError as error:
        raise DiagnosticError([builder.compile_error(str(error))]) from None
    return builder.result(spec, model)


def mjcf(world, time_step: float = 0.002, servo: Servo | None = None) -> str:
    """The world's MuJoCo model as MJCF text (for MuJoCo's own tools), with its initial
    configuration as the keyframe ``initial``."""
    physics = physics_model(world, time_step, servo)
    qpos, act = initial_state(physics, world, world.initial_configuration())
    physics.spec.add_key(name="initial", qpos=qpos.tolist(), act=act.tolist())
    physics.spec.compile()
    return physics.spec.to_xml()


def initial_state(physics: PhysicsModel, world, q: np.ndarray) -> tuple:
    """MuJoCo's ``(qpos, act)`` at the world's configuration ``q`` (pinocchio's ``nq``):
    the joints where ``q`` puts them, each servo's target on its joint, the free bodies
    at their poses."""
    import pinocchio as pin

    model = world.model
    qpos = physics.model.qpos0.copy()
    act = np.zeros(physics.model.na)
    for number, name in enumerate(physics.servoed):
        primary, multiplier, offset = physics.mimics.get(name, (name, 1.0, 0.0))
        joint = model.joints[model.getJointId(primary)]
        value = q[joint.idx_q]
        if joint.nq == 2:
            value = np.arctan2(q[joint.idx_q + 1], q[joint.idx_q])
        value = offset + multiplier * value
        qpos[physics.joints[name][0]] = value
        act[physics.model.actuator_actadr[2 * number]] = value
    poses = world.body_placements(q)
    for body, (address, _, _) in physics.free.items():
        pose = pin.SE3ToXYZQUAT(poses[body])
        qpos[address:address + 3] = pose[:3]
        qpos[address + 3:address + 7] = np.r_[pose[6], pose[3:6]]
    return qpos, act


class _Builder:
    def __init__(self, world, servo: Servo, mujoco):
        self.world = world
        self.servo = servo
        self.mj = mujoco
        self.problems: list = []
        root = ET.fromstring(world.urdf)
        self.links = {link.get("name"): link for link in root.findall("link")}
        self.children: dict = {}
        for joint in root.findall("joint"):
            parent = joint.find("parent").get("link")
            self.children.setdefault(parent, []).append(joint)
        self.meshes: dict = {}
        self.mesh_links: dict = {}
        self.servoed: list = []
        self.mimics: dict = {}
        self.free_joints: dict = {}
        self.limits: dict = {}

    def build(self, time_step: float):
        mj = self.mj
        spec = mj.MjSpec()
        spec.modelname = self.world.path.stem
        spec.compiler.degree = False
        spec.compiler.boundmass = MIN_MASS
        spec.compiler.boundinertia = MIN_MASS
        spec.option.timestep = time_step
        spec.option.integrator = mj.mjtIntegrator.mjINT_IMPLICITFAST
        spec.option.cone = mj.mjtCone.mjCONE_ELLIPTIC
        physics = self.world.physics
        spec.option.gravity = list(physics.gravity)
        self.spec = spec
        self._children(spec.worldbody, ROOT, static=True, carried=False)
        self._mimics()
        self._excludes()
        self._welds()
        self._actuators()
        return spec

    def _children(self, body, link: str, static: bool, carried: bool) -> None:
        """Add the bodies below ``link``: ``static`` when nothing moves ``link``,
        ``carried`` when a free body carries it."""
        for joint in self.children.get(link, ()):
            child = joint.find("child").get("link")
            kind = joint.get("type", "fixed")
            xyz, quat = _origin(joint.find("origin"))
            if kind == "floating":
                if not static:
                    self.problems.append(self._at_link(
                        child, f"the free model '{child}' hangs on a moving body "
                        f"('{link}')", "give it a parent fixed to the world (the default): "
                        "physics moves it; `attach` it to carry it"))
                pose = self.world.body_pose(child, self.world.neutral_configuration())
                added = self.spec.worldbody.add_body(
                    name=child, pos=pose.translation.tolist(),
                    quat=_quaternion(pose.rotation))
                self.free_joints[child] = added.add_freejoint(name=f"{child}_free")
                self._link(added, child, free=True, gravity_compensated=False)
                self._children(added, child, static=False, carried=True)
                continue
            added = body.add_body(name=child, pos=xyz, quat=quat)
            moving = not static or kind != "fixed"
            if kind in ("revolute", "continuous", "prismatic"):
                self._joint(added, joint, kind)
            elif kind == "planar":
                self.problems.append(self._at_link(
                    child, f"the planar joint '{joint.get('name')}' has no MuJoCo "
                    "equivalent", "give the model a fixed, revolute or prismatic joint"))
            self._link(added, child, free=False, gravity_compensated=moving and not carried)
            self._children(added, child, static=not moving, carried=carried)

    def _joint(self, body, element: ET.Element, kind: str) -> None:
        mj = self.mj
        name = element.get("name")
        axis = _floats((element.find("axis").get("xyz") if element.find("axis") is not None
                        else None), (1.0, 0.0, 0.0))
        joint = body.add_joint(name=name, axis=list(axis),
                               type=mj.mjtJoint.mjJNT_SLIDE if kind == "prismatic"
                               else mj.mjtJoint.mjJNT_HINGE)
        limit = element.find("limit")
        if kind != "continuous" and limit is not None:
            lower, upper = float(limit.get("lower", "0")), float(limit.get("upper", "0"))
            if lower < upper:
                joint.range = [lower, upper]
                joint.limited = mj.mjtLimited.mjLIMITED_TRUE
        mimic = element.find("mimic")
        if mimic is not None:
            self.mimics[name] = (mimic.get("joint"), float(mimic.get("multiplier", "1")),
                                 float(mimic.get("offset", "0")))
        effort = float(limit.get("effort", "0")) if limit is not None else 0.0
        if effort > 0 and math.isfinite(effort):
            joint.actfrcrange = [-effort, effort]
            joint.actfrclimited = mj.mjtLimited.mjLIMITED_TRUE
        joint.actgravcomp = True
        self.servoed.append(name)
        velocity = float(limit.get("velocity", "0")) if limit is not None else 0.0
        self.limits[name] = (effort if math.isfinite(effort) else 0.0,
                             velocity if math.isfinite(velocity) else 0.0)

    def _link(self, body, link: str, free: bool, gravity_compensated: bool) -> None:
        element = self.links[link]
        inertial = element.find("inertial")
        mass = inertial.find("mass") if inertial is not None else None
        if free and (mass is None or not float(mass.get("value", "0")) > 0):
            self.problems.append(self._at_link(
                link, f"the free model's link '{link}' has no mass",
                "give it <inertial> with <mass value=\"...\"/> (kg) and <inertia .../>: "
                "physics moves it by its inertia"))
        if inertial is not None and mass is not None and float(mass.get("value", "0")) > 0:
            xyz, quat = _origin(inertial.find("origin"))
            body.mass = float(mass.get("value"))
            body.ipos = xyz
            body.iquat = quat
            body.fullinertia = _inertia(inertial.find("inertia"))
            body.explicitinertial = True
        if gravity_compensated:
            body.gravcomp = 1.0
        for index, collision in enumerate(element.findall("collision")):
            self._geom(body, link, index, collision)

    def _geom(self, body, link: str, index: int, collision: ET.Element) -> None:
        mj = self.mj
        friction = list(self.world.physics.friction)
        condim = 6 if friction[2] > 0 else 4 if friction[1] > 0 else 3
        xyz, quat = _origin(collision.find("origin"))
        geometry = collision.find("geometry")
        shape = geometry[0] if geometry is not None and len(geometry) else None
        common = {"name": f"{link}_collision_{index}", "pos": xyz, "quat": quat,
                  "friction": friction, "condim": condim, "solimp": list(CONTACT_IMPEDANCE),
                  "solref": [max(CONTACT_TIME_CONSTANT, 2 * self.spec.option.timestep), 1.0]}
        if shape is None:
            return
        if shape.tag == "box":
            size = np.array(_floats(shape.get("size"), (0, 0, 0))) / 2
            body.add_geom(type=mj.mjtGeom.mjGEOM_BOX, size=size.tolist(), **common)
        elif shape.tag == "cylinder":
            body.add_geom(type=mj.mjtGeom.mjGEOM_CYLINDER,
                          size=[float(shape.get("radius")), float(shape.get("length")) / 2, 0],
                          **common)
        elif shape.tag == "sphere":
            body.add_geom(type=mj.mjtGeom.mjGEOM_SPHERE,
                          size=[float(shape.get("radius")), 0, 0], **common)
        elif shape.tag == "mesh":
            path = Path(shape.get("filename", ""))
            if path.suffix.lower() not in MESH_FORMATS:
                self.problems.append(self._at_link(
                    link, f"MuJoCo cannot read the collision mesh '{path.name}' of link "
                    f"'{link}' ({path.suffix or 'no extension'})",
                    "give the link a collision mesh in STL, OBJ or MSH, or a primitive "
                    "(box, cylinder, sphere)"))
                return
            scale = _floats(shape.get("scale"), (1.0, 1.0, 1.0))
            key = (str(path), scale)
            if key not in self.meshes:
                self.meshes[key] = f"mesh_{len(self.meshes)}"
                self.spec.add_mesh(name=self.meshes[key], file=str(path), scale=list(scale))
                self.mesh_links[self.meshes[key]] = (link, path)
            body.add_geom(type=mj.mjtGeom.mjGEOM_MESH, meshname=self.meshes[key], **common)

    def _mimics(self) -> None:
        mj = self.mj
        for name, (primary, multiplier, offset) in self.mimics.items():
            self.spec.add_equality(type=mj.mjtEq.mjEQ_JOINT, name1=name, name2=primary,
                                   objtype=mj.mjtObj.mjOBJ_JOINT,
                                   data=[offset, multiplier] + [0.0] * 10)

    def _excludes(self) -> None:
        from ..world.collisions import adjacent_pairs

        for pair in sorted(tuple(sorted(p)) for p in adjacent_pairs(self.world)
                           | self.world.allowed_collisions):
            if ROOT not in pair:
                self.spec.add_exclude(bodyname1=pair[0], bodyname2=pair[1])

    def _welds(self) -> None:
        mj = self.mj
        others = [link for link in self.links if link != ROOT]
        for free in self.free_joints:
            for other in others:
                if other != free:
                    self.spec.add_equality(type=mj.mjtEq.mjEQ_WELD, name=_weld(free, other),
                                           name1=free, name2=other, active=False,
                                           data=[0.0] * 12, solimp=list(WELD_IMPEDANCE),
                                           solref=[max(WELD_TIME_CONSTANT,
                                                       2 * self.spec.option.timestep), 1.0],
                                           objtype=mj.mjtObj.mjOBJ_BODY)

    def _actuators(self) -> None:
        mj = self.mj
        for name in self.servoed:
            kp, kv = self.servo.gains(name)
            target = self.spec.add_actuator(name=f"{name}_target", target=name,
                                            trntype=mj.mjtTrn.mjTRN_JOINT)
            target.set_to_intvelocity(kp=kp, kv=0.0)
            damper = self.spec.add_actuator(name=f"{name}_velocity", target=name,
                                            trntype=mj.mjtTrn.mjTRN_JOINT)
            damper.set_to_velocity(kv=kv)

    def result(self, spec, model) -> PhysicsModel:
        mj = self.mj
        joints = {}
        for name in self.servoed:
            index = mj.mj_name2id(model, mj.mjtObj.mjOBJ_JOINT, name)
            joints[name] = (int(model.jnt_qposadr[index]), int(model.jnt_dofadr[index]))
        free = {}
        for body in self.free_joints:
            index = mj.mj_name2id(model, mj.mjtObj.mjOBJ_JOINT, f"{body}_free")
            free[body] = (int(model.jnt_qposadr[index]), int(model.jnt_dofadr[index]),
                          mj.mj_name2id(model, mj.mjtObj.mjOBJ_BODY, body))
        welds = {(a, b): mj.mj_name2id(model, mj.mjtObj.mjOBJ_EQUALITY, _weld(a, b))
                 for a in self.free_joints for b in self.links if b not in (a, ROOT)}
        return PhysicsModel(spec, model, joints, list(self.servoed), free, welds,
                            dict(self.mimics), dict(self.limits))

    def compile_error(self, message: str) -> Diagnostic:
        """A MuJoCo compile error, located at the link of the mesh it names if any."""
        for mesh, (link, path) in self.mesh_links.items():
            if f"'{mesh}'" in message or str(path) in message:
                return self._at_link(link, f"MuJoCo cannot read the collision mesh "
                                     f"'{path.name}' of link '{link}': "
                                     f"{message.splitlines()[0]}",
                                     "check the file, or give the link a primitive shape")
        return Diagnostic("physics-error", f"MuJoCo refuses the world's model: {message}",
                          str(self.world.path), None)

    def _at_link(self, link: str, message: str, hint: str) -> Diagnostic:
        source = self.world.link_source(link)
        if source is None:
            return Diagnostic("physics-error", message, str(self.world.path), None, hint=hint)
        path, line = source
        text = SourceFile.read(path)
        column = text.line(line).find("<link") + 1 or 1
        return text.error("physics-error", message, Span.point(line, column, len("<link")),
                          hint)


def _weld(free: str, other: str) -> str:
    return f"attach {free} to {other}"


def _floats(text: str | None, default: tuple) -> tuple:
    if text is None:
        return default
    return tuple(float(v) for v in text.split())


def _origin(element: ET.Element | None) -> tuple[list, list]:
    """``(pos, quat)`` (w, x, y, z) of a URDF ``<origin>``."""
    if element is None:
        return [0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]
    import pinocchio as pin

    xyz = list(_floats(element.get("xyz"), (0.0, 0.0, 0.0)))
    rpy = _floats(element.get("rpy"), (0.0, 0.0, 0.0))
    return xyz, _quaternion(pin.rpy.rpyToMatrix(*rpy))


def _quaternion(rotation: np.ndarray) -> list:
    """(w, x, y, z) of a rotation matrix."""
    import pinocchio as pin

    q = pin.Quaternion(np.asarray(rotation, dtype=float)).normalized()
    return [q.w, q.x, q.y, q.z]


def _inertia(element: ET.Element | None) -> list:
    """MuJoCo's ``fullinertia`` (ixx, iyy, izz, ixy, ixz, iyz) [kg m^2]."""
    if element is None:
        return [MIN_MASS] * 3 + [0.0] * 3
    return [float(element.get(key, "0")) for key in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")]
