"""Collision geometry of a world and the pairs of bodies a collision check covers.

The URDFs' ``<collision>`` elements are read by pinocchio into coal shapes; meshes are
replaced by their convex hulls, so that coal's GJK/EPA gives the distance, the witness
points and the normal of every pair. A *set* is a body, or a joint group (or joint)
standing for every body its joints move; only bodies with collision geometry count.

A pair of bodies is left out when the bodies are adjacent (a body and the nearest body
with geometry up its chain of links: what a joint connects), when the world allows it
(a model's SRDF ``disable_collisions``, the world's ``allowed_collisions:``), or when
no joint moves one relative to the other (both carried by the same joint, e.g. two
bodies fixed to the world). :func:`reach` bounds how far a joint's motion carries a
shape; :mod:`~robocop_dsl.world.collision_scene` measures pairs at a kinematic state.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from .world import World

if TYPE_CHECKING:
    import pinocchio as pin


@dataclass(frozen=True)
class Shape:
    """One collision element: the body it belongs to, its placement in the body's frame
    and its coal geometry."""

    name: str
    body: str
    offset: pin.SE3
    geometry: object
    center: np.ndarray
    """Centre of a box bounding it, in the body frame [m]."""
    half: np.ndarray
    """Half extents of that box, along the body frame's axes [m]."""


class CollisionGeometry:
    """Every collision shape of a world, by body (read only, shared by world copies).

    Args:
        urdf: The world's assembled URDF.
    """

    def __init__(self, urdf: str):
        import coal
        import pinocchio as pin

        model = pin.buildModelFromXML(urdf, True)
        geometry_model = pin.buildGeomFromUrdfString(model, urdf, pin.GeometryType.COLLISION)
        shapes = []
        for obj in geometry_model.geometryObjects:
            shape = obj.geometry
            if isinstance(shape, coal.BVHModelBase):
                shape.buildConvexHull(True, "Qt")
                shape = shape.convex
            shape.computeLocalAABB()
            low, high = np.array(shape.aabb_local.min_), np.array(shape.aabb_local.max_)
            frame = model.frames[obj.parentFrame]
            offset = frame.placement.actInv(obj.placement)
            shapes.append(Shape(obj.name, frame.name, offset, shape,
                                offset.act((low + high) / 2),
                                np.abs(offset.rotation) @ ((high - low) / 2)))
        self.shapes: tuple[Shape, ...] = tuple(shapes)
        self.by_body: dict[str, tuple[Shape, ...]] = {}
        for shape in shapes:
            self.by_body.setdefault(shape.body, ())
            self.by_body[shape.body] += (shape,)


@lru_cache(maxsize=16)
def _geometry(urdf: str) -> CollisionGeometry:
    return CollisionGeometry(urdf)


def collision_geometry(world: World) -> CollisionGeometry:
    """The collision shapes of ``world`` (built once per assembled URDF)."""
    return _geometry(world.urdf)


def set_bodies(world: World, name: str) -> tuple[str, ...]:
    """The bodies with collision geometry that set ``name`` stands for, in world order.

    Raises:
        KeyError: ``name`` is neither a body, a joint group nor a joint.
    """
    return bodies_of_set(world, name, collision_geometry(world).by_body)


def bodies_of_set(world: World, name: str, with_geometry) -> tuple[str, ...]:
    """:func:`set_bodies`, given the bodies that have collision geometry (a container
    of names).

    Raises:
        KeyError: ``name`` is neither a body, a joint group nor a joint.
    """
    if world.has_body(name):
        return (name,) if name in with_geometry else ()
    if not world.has_group(name) and name not in world.joint_names():
        raise KeyError(name)
    joints = ({joint.name for joint in world.moving_joints(name)} if world.has_group(name)
              else {name})
    return tuple(body for body in world.body_names()
                 if body in with_geometry and _moved_by(world, body, joints))


def _moved_by(world: World, body: str, joints: set) -> bool:
    """Whether one of ``joints`` lies on the chain of links from ``body`` to the root (a
    mimic joint counting as the joint it follows)."""
    info = world.body(body)
    while info.joint is not None:
        if info.joint in joints or world.joint(info.joint).mimic in joints:
            return True
        info = world.body(info.parent)
    return False


def adjacent_pairs(world: World) -> set:
    """Pairs (frozensets) of a body with geometry and the nearest body with geometry up
    its chain of links."""
    geometry = collision_geometry(world)
    pairs = set()
    for body in geometry.by_body:
        parent = world.body(body).parent
        while parent is not None and parent not in geometry.by_body:
            parent = world.body(parent).parent
        if parent is not None:
            pairs.add(frozenset((body, parent)))
    return pairs


def checked_pairs(world: World, first: str, second: str) -> list[tuple[str, str]]:
    """The pairs of bodies a check between sets ``first`` and ``second`` covers (each
    pair once, in world order), without the pairs left out (see the module).

    Raises:
        KeyError: a set names nothing in the world.
    """
    return _pairs(world, set_bodies(world, first), set_bodies(world, second))


def world_pairs(world: World) -> list[tuple[str, str]]:
    """Every pair of bodies with collision geometry that a check may cover."""
    bodies = tuple(collision_geometry(world).by_body)
    return _pairs(world, bodies, bodies)


def _pairs(world: World, bodies_a, bodies_b) -> list[tuple[str, str]]:
    left_out = adjacent_pairs(world) | world.allowed_collisions
    order = {name: index for index, name in enumerate(world.body_names())}
    carrier = {body: world.model.frames[world.body_frame_id(body)].parentJoint
               for body in set(bodies_a) | set(bodies_b)}
    pairs = set()
    for a in bodies_a:
        for b in bodies_b:
            if a == b or carrier[a] == carrier[b] or frozenset((a, b)) in left_out:
                continue
            pairs.add((a, b) if order[a] < order[b] else (b, a))
    return sorted(pairs, key=lambda pair: (order[pair[0]], order[pair[1]]))


_UNBOUNDED = 1e9
"""Lever arm [m per unit] of a coordinate whose motion is not bounded here (floating
and spherical joints, unlimited prismatic joints): any motion renews the bound."""
_LINEAR = frozenset({"JointModelPX", "JointModelPY", "JointModelPZ",
                     "JointModelPrismaticUnaligned"})
_ANGULAR = frozenset({"JointModelRX", "JointModelRY", "JointModelRZ",
                      "JointModelRevoluteUnaligned"})
_UNBOUNDED_ANGLE = frozenset({"JointModelRUBX", "JointModelRUBY", "JointModelRUBZ",
                              "JointModelRevoluteUnboundedUnaligned"})


def reach(model: pin.Model, frames: list[int], centers: np.ndarray,
          half: np.ndarray) -> np.ndarray:
    """How far each shape can move per unit of each configuration coordinate
    (shapes x nq) [m/rad or m/m], whatever the configuration.

    A revolute joint turning by ``a`` moves a point at most ``a`` times its distance
    to the joint, and that distance is at most the sum of the translations along the
    chain from the joint to the shape plus the shape's radius (prismatic joints below
    add their longest extension). A continuous joint's angle is at most pi/2 times the
    change of its (cos, sin); a prismatic joint moves the shape by its own change; a
    mimic joint is bounded as either, scaled.

    Args:
        model: The kinematic model (frames as placed now).
        frames: The frame each shape is fixed to.
        centers: Each shape's centre in its frame (shapes x 3) [m].
        half: Half extents of each shape's box in its frame (shapes x 3) [m].
    """
    table = np.zeros((len(frames), model.nq))
    for row, (frame_id, center, halves) in enumerate(zip(frames, centers, half)):
        frame = model.frames[frame_id]
        lever = np.linalg.norm(frame.placement.act(center)) + np.linalg.norm(halves)
        joint = frame.parentJoint
        while joint > 0:
            joint_model = model.joints[joint]
            kind, start = joint_model.shortname(), joint_model.idx_q
            extension = 0.0
            if kind in _ANGULAR:
                table[row, start] = lever
            elif kind in _UNBOUNDED_ANGLE:
                table[row, start:start + 2] = lever * np.pi / 2
            elif kind in _LINEAR:
                table[row, start] = 1.0
                extension = _longest(model, start)
            elif kind == "JointModelMimic":
                mimic = joint_model.extract()
                table[row, start] += abs(mimic.scaling) * max(lever, 1.0)
                extension = abs(mimic.scaling) * _longest(model, start) + abs(mimic.offset)
            else:
                stretch = max(joint_model.nq, 1)
                table[row, start:start + stretch] = max(lever, 1.0) * _UNBOUNDED
                extension = _UNBOUNDED
            lever += np.linalg.norm(model.jointPlacements[joint].translation) + extension
            joint = model.parents[joint]
    return table


def _longest(model: pin.Model, index: int) -> float:
    """The largest absolute value coordinate ``index`` may take [m]."""
    longest = max(abs(model.lowerPositionLimit[index]), abs(model.upperPositionLimit[index]))
    return float(longest) if np.isfinite(longest) else _UNBOUNDED


def describe_shape(shape: Shape) -> str:
    """``box 0.09 x 0.09 x 0.14 m``, ``cylinder r 0.06 l 0.2 m``, ``convex 102 points``."""
    import coal

    geometry = shape.geometry
    if isinstance(geometry, coal.Box):
        return "box " + " x ".join(f"{2 * v:.3g}" for v in geometry.halfSide) + " m"
    if isinstance(geometry, coal.Cylinder):
        return f"cylinder r {geometry.radius:.3g} l {2 * geometry.halfLength:.3g} m"
    if isinstance(geometry, coal.Sphere):
        return f"sphere r {geometry.radius:.3g} m"
    if isinstance(geometry, coal.Capsule):
        return f"capsule r {geometry.radius:.3g} l {2 * geometry.halfLength:.3g} m"
    if isinstance(geometry, coal.ConvexBase):
        return f"convex hull of {geometry.num_points} points"
    return type(geometry).__name__.lower()


