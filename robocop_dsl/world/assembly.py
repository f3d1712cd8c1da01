"""Assembling a world: every model's URDF renamed and merged under the ``world`` link,
the attaching joints added, joint groups and initial postures resolved."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

import numpy as np

from ..diagnostics import DiagnosticError, did_you_mean
from .description import ROOT, JointSpec, ModelEntry, Physics, WorldDescription
from .placement import compose, rotation
from .srdf import disabled_pairs
from .urdf import DOFS, JointInfo, UrdfModel, read_urdf


@dataclass
class BodyInfo:
    """A body (URDF link) and the joint that carries it (``None`` for ``world``)."""

    name: str
    parent: str | None
    joint: str | None
    where: str


@dataclass
class GroupInfo:
    """A joint group with its members resolved to joints, in order, without repeats."""

    name: str
    joints: tuple
    members: tuple


@dataclass
class Assembly:
    urdf: str
    bodies: dict = field(default_factory=dict)
    joints: dict = field(default_factory=dict)
    groups: dict = field(default_factory=dict)
    initial: dict = field(default_factory=dict)
    allowed_collisions: set = field(default_factory=set)
    """Pairs of bodies (frozensets) never checked for collisions: SRDFs' and the world's."""
    free: dict = field(default_factory=dict)
    """The root body of each ``free: true`` model -> its :class:`ModelEntry`."""
    links: dict = field(default_factory=dict)
    """Each body of a URDF -> ``(URDF path, line of its <link>)``."""
    physics: Physics = field(default_factory=Physics)


def assemble(description: WorldDescription) -> Assembly:
    """Merge the described models into one URDF and name tables.

    Raises:
        DiagnosticError: with every problem found, the description's included.
    """
    diagnostics: list = list(description.diagnostics)
    robot = ET.Element("robot", name="world")
    ET.SubElement(robot, "link", name=ROOT)
    result = Assembly(urdf="", physics=description.physics)
    result.bodies[ROOT] = BodyInfo(ROOT, None, None, str(description.path))
    attachments = []
    for index, entry in enumerate(description.models):
        urdf = read_urdf(entry.urdf, entry.prefix, f"m{index}_", diagnostics)
        if urdf is None:
            continue
        where = f"{entry.at.source.path}:{entry.at.span.line}"
        duplicate = _first_duplicate(urdf, result)
        if duplicate:
            kind, name, previous = duplicate
            diagnostics.append(entry.at.error(
                "duplicate-name", f"{kind} '{name}' of {urdf.path.name} is already defined ({previous})",
                "give this model a 'namespace:' so that its names are prefixed"))
            continue
        for joint in urdf.joints:
            result.joints[joint.name] = joint
            result.bodies[joint.child] = BodyInfo(joint.child, joint.parent, joint.name,
                                                  joint.where)
        for link in urdf.links:
            if link not in result.bodies:
                result.bodies[link] = BodyInfo(link, None, None, f"{urdf.path}")
            result.links[link] = (urdf.path, urdf.link_lines.get(link, 1))
        if entry.free:
            result.free[urdf.root] = entry
        robot.extend(urdf.elements)
        attachments.append((entry, urdf, where))
        if entry.srdf is not None:
            result.allowed_collisions |= disabled_pairs(entry.srdf, entry.prefix, urdf.links,
                                                        diagnostics)
    for entry, urdf, where in attachments:
        _attach(robot, entry, urdf, where, result, diagnostics)
    result.groups = _resolve_groups(description, result, diagnostics)
    result.initial = _resolve_initial(description, result, diagnostics)
    for first, second, at in description.allowed_collisions:
        unknown = [name for name in (first, second) if name not in result.bodies]
        for name in unknown:
            diagnostics.append(at.error("unknown-body", f"allowed collision names unknown body "
                                        f"'{name}'", did_you_mean(name, result.bodies)))
        if not unknown:
            result.allowed_collisions.add(frozenset((first, second)))
    if diagnostics:
        raise DiagnosticError(diagnostics)
    result.urdf = ET.tostring(robot, encoding="unicode")
    return result


def _first_duplicate(urdf, result: Assembly):
    for link in urdf.links:
        if link in result.bodies:
            return "body", link, result.bodies[link].where
    for joint in urdf.joints:
        if joint.name in result.joints:
            return "joint", joint.name, result.joints[joint.name].where
    return None


def _attach(robot: ET.Element, entry: ModelEntry, urdf: UrdfModel, where: str,
            result: Assembly, diagnostics: list) -> None:
    """Join the model's root link to its ``joint:`` parent.

    The joint's origin is the ``joint:`` position followed by the URDF's own placement
    of its root; a moving joint acts at the root link, about or along the ``axis``
    written in the ``joint:`` frame.
    """
    spec: JointSpec = entry.joint
    root = urdf.root
    if spec.parent not in result.bodies:
        diagnostics.append(spec.parent_at.error(
            "unknown-parent", f"unknown parent body '{spec.parent}'",
            did_you_mean(spec.parent, result.bodies) or "bodies are the links of the models"))
        return
    name = spec.name or f"{spec.parent}_to_{root}"
    if name in result.joints:
        diagnostics.append(entry.at.error(
            "duplicate-name", f"joint '{name}' is already defined ({result.joints[name].where})",
            "give the joint another 'name:'"))
        return
    if spec.type in ("revolute", "prismatic") and not {"lower", "upper", "velocity"} <= set(
            spec.limits):
        diagnostics.append(spec.parent_at.error(
            "invalid-entry", f"a {spec.type} joint needs limits: {{lower: .., upper: .., velocity: ..}}"))
        return
    joint = ET.SubElement(robot, "joint", name=name, type=spec.type)
    ET.SubElement(joint, "parent", link=spec.parent)
    ET.SubElement(joint, "child", link=root)
    xyz, rpy = compose((spec.xyz, spec.rpy), urdf.origin)
    ET.SubElement(joint, "origin", xyz=_text(xyz), rpy=_text(rpy))
    if spec.type in ("revolute", "prismatic", "continuous", "planar"):
        axis = rotation(urdf.origin[1]).T @ np.asarray(spec.axis, float)
        ET.SubElement(joint, "axis", xyz=_text(axis))
    if spec.limits or spec.type in ("revolute", "prismatic"):
        limits = {"lower": 0.0, "upper": 0.0, "velocity": 0.0, "effort": 0.0}
        limits.update(spec.limits)
        ET.SubElement(joint, "limit", **{k: repr(float(v)) for k, v in limits.items()})
    dofs = DOFS[spec.type]
    velocity = float(spec.limits.get("velocity", math.inf)) or math.inf
    bounded = spec.type in ("revolute", "prismatic")
    info = JointInfo(name, spec.type, spec.parent, root, dofs,
                     np.full(dofs, spec.limits["lower"] if bounded else -math.inf),
                     np.full(dofs, spec.limits["upper"] if bounded else math.inf),
                     np.full(dofs, velocity), None, where)
    result.joints[name] = info
    result.bodies[root] = BodyInfo(root, spec.parent, name, where)


def _text(values) -> str:
    return " ".join(repr(float(v)) for v in values)


def _resolve_groups(description: WorldDescription, result: Assembly, diagnostics: list):
    resolved: dict = {}
    names = set(description.groups) | set(result.joints)

    def resolve(name: str, stack: tuple) -> tuple:
        if name in resolved:
            return resolved[name].joints
        entry = description.groups[name]
        joints: list = []
        for member, at in zip(entry.members, entry.member_spans):
            if member in stack:
                diagnostics.append(at.error(
                    "group-cycle", f"joint group '{member}' contains itself: "
                    + " -> ".join(stack[stack.index(member):] + (member,))))
            elif member in description.groups:
                joints.extend(resolve(member, stack + (member,)))
            elif member in result.joints:
                joints.append(member)
            else:
                diagnostics.append(at.error(
                    "unknown-joint", f"joint group '{name}' names unknown joint or group '{member}'",
                    did_you_mean(member, names)))
        resolved[name] = GroupInfo(name, tuple(dict.fromkeys(joints)), tuple(entry.members))
        return resolved[name].joints

    for name in description.groups:
        resolve(name, (name,))
    for name, entry in description.groups.items():
        joints = [result.joints[joint] for joint in resolved[name].joints]
        wide = [joint for joint in joints if joint.dofs > 1]
        if wide:
            diagnostics.append(entry.at.error(
                "invalid-entry", f"joint group '{name}' holds the {wide[0].type} joint "
                f"'{wide[0].name}' ({wide[0].dofs} dofs): a joint group's joints move "
                "along or about one axis",
                "leave it out: controllers and drivers command one-dof joints"))
        elif joints and not any(joint.dofs for joint in joints):
            diagnostics.append(entry.at.error(
                "invalid-entry", f"joint group '{name}' moves nothing: its joints are fixed "
                "or mimic others", "list revolute, continuous or prismatic joints"))
    return resolved


def _resolve_initial(description: WorldDescription, result: Assembly, diagnostics: list):
    initial: dict = {}
    for name, values, at in description.initial:
        if name in result.groups:
            joints = result.groups[name].joints
        elif name in result.joints:
            joints = (name,)
        else:
            diagnostics.append(at.error(
                "unknown-joint", f"initial posture for unknown joint or group '{name}'",
                did_you_mean(name, set(result.groups) | set(result.joints))))
            continue
        dofs = sum(result.joints[j].dofs for j in joints)
        if len(values) != dofs:
            diagnostics.append(at.error(
                "invalid-entry", f"initial posture of '{name}' has {len(values)} values, "
                f"the group has {dofs} dofs"))
            continue
        offset = 0
        for joint in joints:
            count = result.joints[joint].dofs
            initial[joint] = np.array(values[offset:offset + count])
            offset += count
    return initial
