"""Collision geometry of a world and the pairs of bodies a collision check covers.

The URDFs' ``<collision>`` elements are read by pinocchio into coal shapes; meshes are
replaced by their convex hulls, so that coal's GJK/EPA gives the distance, the witness
points and the normal of every pair. A *set* is a body, or a joint group (or joint)
standing for every body its joints move; only bodies with collision geometry count.

A pair of bodies is left out when the bodies are adjacent (a body and the nearest body
with geometry up its chain of links: what a joint connects), when the world allows it
(a model's SRDF ``disable_collisions``, the world's ``allowed_collisions:``), or when
no joint moves one relative to the other (both carried by the same joint, e.g. two
bodies fixed to the world).

A :class:`CollisionScene` places the shapes of some pairs at a kinematic state: a broad
phase on world-aligned boxes (a lower bound of the distance, in numpy) selects the
pairs that may be close, and only those are handed to coal. Followed from cycle to
cycle (:meth:`CollisionScene.near`), a pair keeps the lower bound of its distance found
the last time it was looked at, minus how far the joints have moved its shapes since
(:func:`reach`: a lever arm per shape and joint coordinate): coal runs again only on the
pairs whose bound falls below the distance asked for.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from operator import attrgetter
from typing import NamedTuple
from weakref import WeakKeyDictionary

import coal
import numpy as np
import pinocchio as pin

from .world import World


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


class Witness(NamedTuple):
    """The closest points of a pair of shapes at one state (world frame, metres).

    ``normal`` is the unit direction from ``first`` to ``second``; ``distance`` is
    negative when the shapes overlap (then it is the penetration depth)."""

    first: Shape
    second: Shape
    distance: float
    point_first: np.ndarray
    point_second: np.ndarray
    normal: np.ndarray


class CollisionGeometry:
    """Every collision shape of a world, by body (read only, shared by world copies).

    Args:
        urdf: The world's assembled URDF.
    """

    def __init__(self, urdf: str):
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


_POSES: WeakKeyDictionary = WeakKeyDictionary()


def _body_poses(kinematics, frames: list[int]) -> np.ndarray:
    """The 4 x 4 world poses of ``frames`` at the kinematics' current state, stacked;
    computed once per state for every scene that asks."""
    stamp, poses = _POSES.get(kinematics, (None, None))
    if stamp != kinematics.stamp:
        poses = {}
        _POSES[kinematics] = (kinematics.stamp, poses)
    for frame in frames:
        if frame not in poses:
            poses[frame] = kinematics.pose(frame).homogeneous
    return np.array([poses[frame] for frame in frames])


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
    geometry = collision_geometry(world)
    if world.has_body(name):
        return (name,) if name in geometry.by_body else ()
    if not world.has_group(name) and name not in world.joint_names():
        raise KeyError(name)
    joints = set(world.joint_group(name).joints) if world.has_group(name) else {name}
    return tuple(body for body in world.body_names()
                 if body in geometry.by_body and _moved_by(world, body, joints))


def _moved_by(world: World, body: str, joints: set) -> bool:
    """Whether one of ``joints`` lies on the chain of links from ``body`` to the root."""
    info = world.body(body)
    while info.joint is not None:
        if info.joint in joints:
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


_LEVI_CIVITA = np.zeros((3, 3, 3))
_LEVI_CIVITA[0, 1, 2] = _LEVI_CIVITA[1, 2, 0] = _LEVI_CIVITA[2, 0, 1] = 1.0
_LEVI_CIVITA[0, 2, 1] = _LEVI_CIVITA[2, 1, 0] = _LEVI_CIVITA[1, 0, 2] = -1.0
"""``a x b = einsum("ijk,j,k->i", _LEVI_CIVITA, a, b)``."""
_distance = attrgetter("distance")
_MEASURED_ALONE = 8
"""Above this many pairs to measure at once that were not near at the last call, every
pair's bound is renewed from its boxes first (one vectorised pass) so that coal sees
only the pairs still close."""
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


class CollisionScene:
    """The shapes of some pairs of bodies, placed at a kinematic state.

    :meth:`place` puts a box around every shape, from its body's pose at the state of
    a :class:`~robocop_dsl.control.kinematics.Kinematics` (shared with the tasks that
    read the same poses; a body attached at run time carries its shapes);
    :meth:`box_distances` bound the pairs' distances from below; :meth:`witness` runs
    coal on one pair, placing its two shapes on first use at that state.

    Args:
        world: The world whose model the kinematics use.
        pairs: Pairs of body names (see :func:`checked_pairs`).
    """

    def __init__(self, world: World, pairs: list[tuple[str, str]]):
        geometry = collision_geometry(world)
        bodies = list(dict.fromkeys(body for pair in pairs for body in pair))
        self.shapes: list[Shape] = [s for body in bodies for s in geometry.by_body[body]]
        index = {id(shape): i for i, shape in enumerate(self.shapes)}
        self.model = pin.GeometryModel()
        for shape in self.shapes:
            self.model.addGeometryObject(pin.GeometryObject(
                shape.name, 0, 0, pin.SE3.Identity(), shape.geometry))
        first, second = [], []
        for a, b in pairs:
            for shape_a in geometry.by_body[a]:
                for shape_b in geometry.by_body[b]:
                    first.append(index[id(shape_a)])
                    second.append(index[id(shape_b)])
                    self.model.addCollisionPair(pin.CollisionPair(first[-1], second[-1]))
        self.first = np.array(first, dtype=int)
        self.second = np.array(second, dtype=int)
        self.data = pin.GeometryData(self.model)
        for request in self.data.distanceRequests:
            request.enable_signed_distance = True
        self.frames = [world.body_frame_id(body) for body in bodies]
        """Frame id of each body of the scene."""
        self._frame_of = [world.body_frame_id(shape.body) for shape in self.shapes]
        self._body_of = np.array([bodies.index(shape.body) for shape in self.shapes], dtype=int)
        self._centers = np.array([s.center for s in self.shapes]).reshape(-1, 3)
        self._half = np.array([s.half for s in self.shapes]).reshape(-1, 3)
        radius = np.linalg.norm(self._half, axis=1)
        self._radii = radius[self.first] + radius[self.second]
        self.centers = np.zeros((len(self.shapes), 3))
        self.half = np.zeros((len(self.shapes), 3))
        self._kinematics = None
        self._stamp = -1
        self._placed = -1
        self._bound_to = None
        self._followed = None
        self._pair_reach = np.zeros((len(first), 0))
        self._levers = np.ones(len(first))
        """Each pair's longest lever in ``_pair_reach`` [m per unit]."""
        self._lower = np.zeros(len(first))
        self._pair_shapes = [(self.shapes[a], self.shapes[b]) for a, b in zip(first, second)]
        self._was_near: set[int] = set()
        self._reference = np.zeros(0)
        self._moved = np.zeros(world.model.nq)
        self._within = np.nan
        self._still = 0.0
        self._joint_of: dict[int, int] = {}
        """Joint carrying each shape (by ``id``), as bound by :meth:`_place_shapes`."""

    @property
    def size(self) -> int:
        """Number of shape pairs."""
        return len(self.first)

    def place(self, kinematics) -> None:
        """Put the shapes' world-aligned bounding boxes at the current state of
        ``kinematics``."""
        self._kinematics, self._stamp = kinematics, kinematics.stamp
        if not self.shapes:
            return
        poses = _body_poses(kinematics, self.frames)[self._body_of]
        rotations = poses[:, :3, :3]
        np.add(np.einsum("mij,mj->mi", rotations, self._centers), poses[:, :3, 3],
               out=self.centers)
        np.einsum("mij,mj->mi", np.abs(rotations), self._half, out=self.half)

    def box_distances(self) -> np.ndarray:
        """A lower bound of every shape pair's distance [m] (after :meth:`place`): the
        larger of the distance between their world bounding boxes and the distance
        between the balls around those boxes' centres."""
        centers, half = self.centers, self.half
        first, second = self.first, self.second
        offset = centers[first] - centers[second]
        balls = np.sqrt(np.einsum("ij,ij->i", offset, offset)) - self._radii
        gap = np.abs(offset, out=offset)
        gap -= half[first]
        gap -= half[second]
        np.maximum(gap, 0.0, out=gap)
        return np.maximum(np.sqrt(np.einsum("ij,ij->i", gap, gap)), balls)

    def _place_shapes(self) -> None:
        """Place every shape at the current state (pinocchio, once per state), each
        carried by the joint its body's frame hangs on now."""
        if self._placed == self._stamp:
            return
        kinematics = self._kinematics
        if self._bound_to != (kinematics, kinematics.placements):
            self._bound_to = (kinematics, kinematics.placements)
            frames = kinematics.model.frames
            for obj, shape, frame_id in zip(self.model.geometryObjects, self.shapes,
                                            self._frame_of):
                frame = frames[frame_id]
                obj.parentJoint = self._joint_of[id(shape)] = frame.parentJoint
                obj.placement = frame.placement * shape.offset
        pin.updateGeometryPlacements(kinematics.model, kinematics.data, self.model, self.data)
        self._placed = self._stamp

    def witness(self, index: int) -> Witness:
        """Distance, closest points and normal of shape pair ``index`` (after :meth:`place`
        or :meth:`near`)."""
        self._place_shapes()
        return self._measure(int(index))

    def _measure(self, index: int) -> Witness:
        """Coal's distance, closest points and normal of shape pair ``index``, the shapes
        being placed at the current state."""
        result = pin.computeDistance(self.model, self.data, index)
        return Witness(*self._pair_shapes[index], result.min_distance,
                       result.getNearestPoint1(), result.getNearestPoint2(),
                       result.normal.copy())

    def closest(self, below: float = np.inf) -> list[Witness]:
        """Every shape pair closer than ``below`` [m], closest first (after :meth:`place`)."""
        found = [self.witness(i) for i in np.flatnonzero(self.box_distances() < below)]
        return sorted((w for w in found if w.distance < below), key=_distance)

    def near(self, kinematics, within: float) -> list[Witness]:
        """The shape pairs closer than ``within`` [m] at the current state of
        ``kinematics``, closest first, followed from call to call.

        Each pair keeps a lower bound of its distance at a reference configuration;
        at another configuration the bound is lowered by the pair's :func:`reach` times
        how far each joint coordinate is from the reference. While the joints have
        moved less in all (the sum of their coordinates' changes) than the smallest
        margin any pair's bound leaves above ``within`` divided by that pair's longest
        lever, no pair can be within: the call costs a subtraction and a sum. Else the
        pairs whose bound falls below ``within`` are measured by coal, every bound is
        moved to the current configuration, which becomes the reference. The boxes of
        :meth:`place` bound every pair on the first call, after an attachment, and when
        many pairs that were not near need measuring at once.
        """
        q = kinematics.q
        self._kinematics, self._stamp = kinematics, kinematics.stamp
        moved = self._moved
        if self._followed != (kinematics, kinematics.placements):
            self._followed = (kinematics, kinematics.placements)
            shape_reach = reach(kinematics.model, self._frame_of, self._centers, self._half)
            self._pair_reach = shape_reach[self.first] + shape_reach[self.second]
            self._levers = np.maximum(self._pair_reach.max(axis=1, initial=0.0), 1e-12)
            self._reference = q.copy()
            self._renew_all(kinematics)
            moved[:] = 0.0
        else:
            np.subtract(q, self._reference, out=moved)
            np.abs(moved, out=moved)
            if self._still and within == self._within and moved.sum() < self._still:
                return []
        lower = self._lower - self._pair_reach @ moved
        candidates = np.flatnonzero(lower < within).tolist()
        if len(set(candidates).difference(self._was_near)) > _MEASURED_ALONE:
            self._renew_all(kinematics)
            lower = self._lower
            candidates = np.flatnonzero(lower < within).tolist()
        found, near = [], set()
        if candidates:
            self._place_shapes()
            for index in candidates:
                witness = self._measure(index)
                lower[index] = witness.distance
                if witness.distance < within:
                    found.append(witness)
                    near.add(index)
        self._follow_from(q, lower, within, near)
        found.sort(key=_distance)
        return found

    def _follow_from(self, q: np.ndarray, lower: np.ndarray, within: float,
                     near: set) -> None:
        """Make ``q`` the reference configuration, with bounds ``lower`` [m] and the
        pairs ``near`` (indices) within ``within`` [m]."""
        self._reference[:] = q
        self._lower = lower
        self._within = within
        self._was_near = near
        if near or not self.size:
            self._still = 0.0 if near else np.inf
            return
        self._still = float(np.min((lower - within) / self._levers))

    def distance_jacobian(self, witnesses: list[Witness]) -> np.ndarray:
        """How fast each witness's distance changes per joint velocity (len x nv)
        [m/s per rad/s or m/s]: the velocity of its second point minus that of its
        first, along its normal, each point carried by the joint its shape hangs on
        (after :meth:`near` or :meth:`witness` at the current state).

        With a joint's Jacobian in the world frame ``J = [v0; w]`` (``v0`` the velocity
        of the point of its body at the world's origin), a point ``p`` moves at
        ``v0 + w x p``, so its speed along ``n`` is ``[n; p x n] . J``."""
        count = len(witnesses)
        jacobian, joint_of = self._kinematics.joint_jacobian, self._joint_of
        stacked = np.array([[jacobian(joint_of[id(w.first)]) for w in witnesses],
                            [jacobian(joint_of[id(w.second)]) for w in witnesses]])
        points = np.array([[w.point_first for w in witnesses],
                           [w.point_second for w in witnesses]])
        weights = np.empty((2, count, 6))
        normals = weights[..., :3]
        normals[1] = [w.normal for w in witnesses]
        np.negative(normals[1], out=normals[0])
        np.einsum("ijk,pnj,pnk->pni", _LEVI_CIVITA, points, normals, out=weights[..., 3:])
        return np.einsum("pne,pned->nd", weights, stacked)

    def _renew_all(self, kinematics) -> None:
        """Bound every pair by its boxes at the current state."""
        self.place(kinematics)
        self._lower = self.box_distances()

    def clearance(self) -> float:
        """The smallest distance over every pair [m] (``inf`` without pairs; after
        :meth:`place`)."""
        boxes = self.box_distances()
        best = np.inf
        for index in np.argsort(boxes):
            if boxes[index] >= best:
                break
            best = min(best, self.witness(index).distance)
        return float(best)
