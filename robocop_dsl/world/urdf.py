"""Reading one URDF: its links and joints with their source lines, renamed into a
namespace, with mesh URIs resolved to absolute paths."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from xml.parsers import expat

import numpy as np

from ..diagnostics import SourceFile, Span
from ..sources import URDF, UnreadableSource, read_source
from . import paths
from .description import ROOT, prefixed
from .meshes import lfs_pointer, load_problems, mesh_refusal
from .placement import IDENTITY
from .urdf_geometry import check_geometry
from .urdf_positions import ElementPositions
from .urdf_values import UrdfValues

DOFS = {"fixed": 0, "revolute": 1, "continuous": 1, "prismatic": 1, "floating": 6,
        "planar": 3}
_MESH_FORMATS = "a mesh is a regular file in STL, COLLADA (.dae), OBJ, PLY or MSH"


@dataclass
class JointInfo:
    """A joint of the world: type, bodies it links and limits (SI: rad or m, rad/s or m/s).

    ``dofs`` counts velocity coordinates; a mimic joint has none of its own. A
    velocity limit of 0 (written by some URDFs for "unknown") counts as none.
    """

    name: str
    type: str
    parent: str
    child: str
    dofs: int
    lower: np.ndarray
    upper: np.ndarray
    max_velocity: np.ndarray
    mimic: str | None = None
    where: str = ""


@dataclass
class UrdfModel:
    """A URDF's elements after renaming, ready to merge into the world's URDF.

    ``origin`` is the root link's ``(xyz, rpy)`` placement (m, rad) in the model's
    frame: the URDF's own fixed joint from its ``world`` link, if it has one.
    """

    path: Path
    root: str | None
    origin: tuple = IDENTITY
    links: list = field(default_factory=list)
    joints: list = field(default_factory=list)
    elements: list = field(default_factory=list)
    link_lines: dict = field(default_factory=dict)
    joint_lines: dict = field(default_factory=dict)


def element_lines(text: str) -> dict:
    """Map ('link'|'joint', name) to the 1-based line of its element."""
    lines: dict = {}
    parser = expat.ParserCreate()

    def start(tag, attrs):
        if tag in ("link", "joint") and "name" in attrs:
            lines.setdefault((tag, attrs["name"]), parser.CurrentLineNumber)

    parser.StartElementHandler = start
    try:
        parser.Parse(text, True)
    except expat.ExpatError:
        pass
    return lines


def _floats(text: str | None, default: tuple) -> tuple:
    if text is None:
        return default
    return tuple(float(v) for v in text.split())


def joint_info(element: ET.Element, where: str) -> JointInfo:
    """Describe a (renamed) URDF ``<joint>`` element."""
    kind = element.get("type", "fixed")
    dofs = DOFS.get(kind, 0)
    limit = element.find("limit")
    mimic = element.find("mimic")
    lower = np.full(dofs, -math.inf)
    upper = np.full(dofs, math.inf)
    velocity = np.full(dofs, math.inf)
    if limit is not None and kind in ("revolute", "prismatic"):
        lower[:] = float(limit.get("lower", "-inf"))
        upper[:] = float(limit.get("upper", "inf"))
    if limit is not None and limit.get("velocity") and dofs:
        velocity[:] = float(limit.get("velocity")) or math.inf
    if mimic is not None:
        kind_dofs = 0
        return JointInfo(element.get("name"), "mimic", element.find("parent").get("link"),
                         element.find("child").get("link"), kind_dofs, np.zeros(0),
                         np.zeros(0), np.zeros(0), mimic.get("joint"), where)
    return JointInfo(element.get("name"), kind, element.find("parent").get("link"),
                     element.find("child").get("link"), dofs, lower, upper, velocity,
                     None, where)


def read_urdf(path: Path, prefix: str, material_prefix: str,
              diagnostics: list) -> UrdfModel | None:
    """Read ``path`` and rename its links and joints into namespace ``prefix``.

    Problems (malformed XML, bad numbers or shapes, meshes that are not found, may not
    be read or, for collision meshes, do not load, a tree without a single root) are
    appended to ``diagnostics``; ``None`` is returned when the file is unusable.
    """
    try:
        source = read_source(path, URDF)
    except UnreadableSource as error:
        diagnostics.extend(error.diagnostics)
        return None
    try:
        robot = ET.fromstring(source.text)
    except ET.ParseError as error:
        line, column = error.position
        diagnostics.append(source.error("urdf-error", f"malformed URDF: {error.msg}",
                                        Span.point(line, column + 1)))
        return None
    lines = element_lines(source.text)
    positions = ElementPositions(source, robot)
    values = UrdfValues(source, diagnostics)
    readable = [values.link(link, lines.get(("link", link.get("name")), 1))
                for link in robot.findall("link")]
    readable += [values.joint(joint, lines.get(("joint", joint.get("name")), 1))
                 for joint in robot.findall("joint")]
    readable += [values.unique(robot.findall(tag), tag, lines) for tag in ("link", "joint")]
    if not all(readable):
        return None
    for link in robot.findall("link"):
        check_geometry(link, positions, diagnostics)
    model = UrdfModel(path, None)
    rename = {}
    for link in robot.findall("link"):
        new = prefixed(prefix, link.get("name", ""))
        rename[link.get("name")] = new
        model.link_lines[new] = lines.get(("link", link.get("name")), 1)
        link.set("name", new)
        model.links.append(new)
    joint_names = {j.get("name"): prefixed(prefix, j.get("name", ""))
                   for j in robot.findall("joint")}
    children = set()
    for joint in robot.findall("joint"):
        line = lines.get(("joint", joint.get("name")), 1)
        for tag in ("parent", "child"):
            ref = joint.find(tag)
            if ref is None or ref.get("link") not in rename:
                diagnostics.append(source.error(
                    "urdf-error", f"joint '{joint.get('name')}' has no valid <{tag}> link",
                    Span.point(line)))
                return None
            ref.set("link", rename[ref.get("link")])
        children.add(joint.find("child").get("link"))
        mimic = joint.find("mimic")
        if mimic is not None:
            mimic.set("joint", joint_names.get(mimic.get("joint"), mimic.get("joint")))
        joint.set("name", joint_names[joint.get("name")])
        model.joint_lines[joint.get("name")] = line
        model.joints.append(joint_info(joint, f"{path}:{line}"))
    for material in robot.iter("material"):
        if material.get("name"):
            material.set("name", material_prefix + material.get("name"))
    _resolve_meshes(robot, positions, diagnostics)
    roots = [name for name in model.links if name not in children]
    if len(roots) != 1:
        diagnostics.append(source.error(
            "urdf-error", f"a URDF must have exactly one root link, found {len(roots)}"
            + (f": {', '.join(roots)}" if roots else ""), Span.point(1)))
        return None
    model.root = roots[0]
    if ROOT in model.links and not _fold_world(robot, model, source, diagnostics):
        return None
    model.elements = [e for e in robot if e.tag in ("link", "joint", "material")]
    return model


def _fold_world(robot: ET.Element, model: UrdfModel, source: SourceFile,
                diagnostics: list) -> bool:
    """Drop the URDF's own ``world`` link and the fixed joint from it: the joint's
    child becomes the root, placed by the joint's origin."""
    joints = [j for j in robot.findall("joint") if j.find("parent").get("link") == ROOT]
    if model.root != ROOT or len(joints) != 1 or joints[0].get("type") != "fixed":
        diagnostics.append(source.error(
            "urdf-error", "a URDF's 'world' link must be its root with one fixed joint "
            "to the robot's base", Span.point(model.link_lines[ROOT]),
            "remove the 'world' link and place the model with 'joint:' in the world file"))
        return False
    [joint] = joints
    origin = joint.find("origin")
    if origin is not None:
        model.origin = (_floats(origin.get("xyz"), IDENTITY[0]),
                        _floats(origin.get("rpy"), IDENTITY[1]))
    robot.remove(joint)
    robot.remove(next(link for link in robot.findall("link") if link.get("name") == ROOT))
    model.links.remove(ROOT)
    model.joints = [j for j in model.joints if j.name != joint.get("name")]
    model.root = joint.find("child").get("link")
    return True


def _resolve_meshes(robot: ET.Element, positions: ElementPositions,
                    diagnostics: list) -> None:
    """Set each mesh's filename to the file it resolves to; report the meshes not found,
    those that may not be read and the collision meshes coal's loader refuses."""
    source = positions.source
    folder = Path(source.path).parent
    collision = []
    for link in robot.findall("link"):
        name = link.get("name")
        collision_meshes = {id(mesh) for element in link.findall("collision")
                            for mesh in element.iter("mesh")}
        for mesh in link.iter("mesh"):
            uri = mesh.get("filename")
            if not uri:
                continue
            span = positions.span(mesh, "filename")
            found = paths.resolve(uri, folder)
            refused = found and mesh_refusal(uri, found)
            if found is None:
                diagnostics.append(source.error(
                    "mesh-not-found", f"cannot find mesh '{uri}' of link '{name}'", span,
                    "package:// URIs resolve along the robots path "
                    "(the URDF's folder, robots/, ROBOCOP_PATH)"))
            elif refused:
                diagnostics.append(source.error(
                    "mesh-error", f"cannot read mesh '{uri}' of link '{name}': {refused}",
                    span, _MESH_FORMATS))
            else:
                mesh.set("filename", str(found))
                if id(mesh) in collision_meshes:
                    collision.append((found, uri, name, span))
    problems = load_problems([found for found, *_ in collision])
    for found, uri, name, span in collision:
        if found in problems:
            diagnostics.append(source.error(
                "mesh-error", f"cannot load mesh '{uri}' of link '{name}': {problems[found]}",
                span, "the file is a Git LFS pointer, not the mesh: fetch it with "
                "'git lfs pull'" if lfs_pointer(found) else _MESH_FORMATS))

