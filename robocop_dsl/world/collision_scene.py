"""The shapes of some pairs of bodies placed at a kinematic state, measured by coal.

A :class:`CollisionScene` puts a world-aligned box around each shape (a lower bound of
every pair's distance, in numpy) and hands to coal only the pairs that may be close.
Followed from cycle to cycle (:meth:`CollisionScene.nearby`), a pair keeps the lower
bound of its distance found the last time it was measured, minus how far the joints
have moved its shapes since (:func:`~robocop_dsl.world.collisions.reach`: a lever arm
per shape and joint coordinate): coal runs again only on the pairs whose bound falls
below the distance asked for. What coal finds comes back as arrays (:class:`Nearby`),
and :meth:`CollisionScene.distance_rows` turns them into the rate of each distance per
joint velocity in a few vectorised products.
"""

from __future__ import annotations

from typing import NamedTuple
from weakref import WeakKeyDictionary

import numpy as np
import pinocchio as pin

from .collisions import Shape, collision_geometry, reach
from .world import World

_MEASURED_ALONE = 8
"""Above this many pairs to measure at once that were not near at the last call, every
pair's bound is renewed from its boxes first (one vectorised pass) so that coal sees
only the pairs still close."""
_CROSS = np.zeros((3, 3, 3))
_CROSS[0, 1, 2] = _CROSS[1, 2, 0] = _CROSS[2, 0, 1] = 1.0
_CROSS[0, 2, 1] = _CROSS[2, 1, 0] = _CROSS[1, 0, 2] = -1.0
_CROSS = _CROSS.transpose(1, 2, 0).reshape(9, 3)
"""``a x b = outer(a, b).ravel() @ _CROSS`` (the Levi-Civita symbol, flattened)."""


class Witness(NamedTuple):
    """The closest points of a pair of shapes at one state (world frame, metres).

    ``normal`` is the unit direction from ``first`` to ``second``; ``distance`` is
    negative when the shapes overlap (then it is the penetration depth); ``pair`` is
    the shape pair's index in the scene that measured it."""

    first: Shape
    second: Shape
    distance: float
    point_first: np.ndarray
    point_second: np.ndarray
    normal: np.ndarray
    pair: int


class Nearby(NamedTuple):
    """Shape pairs of a scene measured at one state, as arrays (world frame)."""

    pairs: np.ndarray
    """The pairs' indices in the scene."""
    distances: np.ndarray
    """[m], negative when the shapes overlap."""
    points: np.ndarray
    """pairs x 3: the closest points on the first shapes [m] (those on the second shapes
    are ``points + distances * normals``)."""
    normals: np.ndarray
    """pairs x 3: unit directions from the first shape to the second."""

    def subset(self, keep) -> Nearby:
        """The pairs ``keep`` (indices, a mask or a slice) selects, in its order."""
        return Nearby(self.pairs[keep], self.distances[keep], self.points[keep],
                      self.normals[keep])


NOTHING_NEAR = Nearby(np.zeros(0, dtype=int), np.zeros(0), np.zeros((0, 3)),
                      np.zeros((0, 3)))

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


def _same(within, other) -> bool:
    """Whether two ``within`` of :meth:`CollisionScene.nearby` are the same distances."""
    return within is other or (isinstance(within, float) and isinstance(other, float)
                                and within == other)


class CollisionScene:
    """The shapes of some pairs of bodies, placed at a kinematic state.

    :meth:`place` puts a box around every shape, from its body's pose at the state of
    a :class:`~robocop_dsl.control.kinematics.Kinematics` (shared with the tasks that
    read the same poses; a body attached at run time carries its shapes);
    :meth:`box_distances` bound the pairs' distances from below; :meth:`measure` runs
    coal on some pairs, placing the shapes on first use at that state.

    Args:
        world: The world whose model the kinematics use.
        pairs: Pairs of body names (see :func:`~robocop_dsl.world.collisions.
            checked_pairs`).
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
        self.data.deactivateAllCollisionPairs()
        self._results = list(self.data.distanceResults)
        """Each pair's coal result, updated in place by every measure."""
        self._active: set[int] = set()
        self._active_of: np.ndarray | None = None
        self._active_bytes = b""
        self._active_results: list = []
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
        self._prepared_for: tuple | None = None
        self._pair_reach = np.zeros((len(first), 0))
        self._levers = np.ones(len(first))
        """Each pair's longest lever in ``_pair_reach`` [m per unit]."""
        self._lower = np.zeros(len(first))
        self._pair_shapes = [(self.shapes[a], self.shapes[b]) for a, b in zip(first, second)]
        self._was_near = np.zeros(0, dtype=int)
        self._was_near_within = np.zeros(0)
        self._reference = np.zeros(0)
        self._moved = np.zeros(world.model.nq)
        self._ones = np.ones(world.model.nq)
        self._within = np.nan
        self._still = -np.inf
        self._pair_signs = np.zeros((len(first), 0))
        """Per pair, +1 for the joint coordinates that move only its second shape, -1 for
        those that move only its first (pairs x nvExtended), as bound by
        :meth:`_place_shapes`."""
        self._basis_key: tuple = ()
        self._basis: tuple = ()

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
        self._bind(kinematics)
        pin.updateGeometryPlacements(kinematics.model, kinematics.data, self.model, self.data)
        self._placed = self._stamp

    def _bind(self, kinematics) -> None:
        """Hang every shape on the joint its body's frame hangs on in ``kinematics`` now
        (once per set of frame placements)."""
        key = (kinematics, kinematics.placements)
        if self._bound_to == key:
            return
        self._bound_to = key
        frames = kinematics.model.frames
        joints = []
        for obj, shape, frame_id in zip(self.model.geometryObjects, self.shapes,
                                        self._frame_of):
            frame = frames[frame_id]
            obj.parentJoint = frame.parentJoint
            obj.placement = frame.placement * shape.offset
            joints.append(frame.parentJoint)
        supports = kinematics.supports[np.array(joints, dtype=int)]
        self._pair_signs = supports[self.second] - supports[self.first]

    def measure(self, indices: np.ndarray) -> Nearby:
        """Coal's distances, closest points and normals of shape pairs ``indices`` (an
        int array, kept as the result's ``pairs``), in their order, at the state of the
        last :meth:`place` or :meth:`nearby`."""
        if not indices.size:
            return NOTHING_NEAR
        self._place_shapes()
        results = self._activate(indices)
        pin.computeDistances(self.model, self.data)
        vectors = np.concatenate([vector for result in results
                                  for vector in (result.getNearestPoint1(), result.normal)])
        vectors = vectors.reshape(-1, 2, 3)
        return Nearby(indices, np.array([result.min_distance for result in results]),
                      vectors[:, 0], vectors[:, 1])

    def _activate(self, indices: np.ndarray) -> list:
        """Make pairs ``indices`` the only ones pinocchio's ``computeDistances`` measures
        (kept while the same array comes back); their results, in order."""
        if indices is not self._active_of and indices.tobytes() != self._active_bytes:
            self._active_bytes = indices.tobytes()
            wanted = indices.tolist()
            active, data, chosen = self._active, self.data, set(wanted)
            for index in active - chosen:
                data.deactivateCollisionPair(index)
            for index in chosen - active:
                data.activateCollisionPair(index)
            self._active = chosen
            self._active_of = indices
            self._active_results = [self._results[index] for index in wanted]
        return self._active_results

    def witnesses(self, nearby: Nearby) -> list[Witness]:
        """The pairs of ``nearby`` as :class:`Witness` records, in its order."""
        shapes = self._pair_shapes
        seconds = nearby.points + nearby.distances[:, None] * nearby.normals
        return [Witness(*shapes[pair], float(distance), first, second, normal, int(pair))
                for pair, distance, first, second, normal
                in zip(nearby.pairs, nearby.distances, nearby.points, seconds,
                       nearby.normals)]

    def witness(self, index: int) -> Witness:
        """Distance, closest points and normal of shape pair ``index`` (after :meth:`place`
        or :meth:`nearby`)."""
        return self.witnesses(self.measure(np.array([index], dtype=int)))[0]

    def closest(self, below: float = np.inf) -> list[Witness]:
        """Every shape pair closer than ``below`` [m], closest first (after :meth:`place`)."""
        measured = self.measure(np.flatnonzero(self.box_distances() < below))
        return _by_distance(self.witnesses(_closer(measured, below)))

    def near(self, kinematics, within) -> list[Witness]:
        """:meth:`nearby` as :class:`Witness` records, closest first."""
        return _by_distance(self.witnesses(self.nearby(kinematics, within)))

    def prepare(self, kinematics) -> None:
        """Compute, for the frames as ``kinematics`` places them now, each pair's
        :func:`reach` (what :meth:`nearby` needs whatever the state), so that the first
        call to :meth:`nearby` does not; needs no state."""
        key = (kinematics, kinematics.placements)
        if self._prepared_for == key:
            return
        shape_reach = reach(kinematics.model, self._frame_of, self._centers, self._half)
        self._pair_reach = shape_reach[self.first] + shape_reach[self.second]
        self._levers = np.maximum(self._pair_reach.max(axis=1, initial=0.0), 1e-12)
        self._bind(kinematics)
        self._prepared_for = key

    def nearby(self, kinematics, within) -> Nearby:
        """The shape pairs closer than ``within`` [m] (one distance, or one per pair) at
        the current state of ``kinematics``, in the scene's order, followed from call to
        call.

        Each pair keeps a lower bound of its distance at a reference configuration;
        at another configuration the bound is lowered by the pair's :func:`reach` times
        how far each joint coordinate is from the reference. While the joints have
        moved less in all (the sum of their coordinates' changes) than the smallest
        margin any pair's bound leaves above ``within`` divided by that pair's longest
        lever, no pair but those within at the reference can be within: the call costs
        a subtraction, a sum and coal's measures of those pairs. Else the pairs whose
        bound falls below ``within`` are measured by coal, every bound is moved to the
        current configuration, which becomes the reference. The boxes of :meth:`place`
        bound every pair on the first call, after an attachment, and when many pairs
        that were not near need measuring at once. An array ``within`` is taken to be
        unchanged while it is the same object.
        """
        q = kinematics.q
        self._kinematics, self._stamp = kinematics, kinematics.stamp
        moved = self._moved
        followed = self._followed
        if followed is None or followed[0] is not kinematics \
                or followed[1] != kinematics.placements:
            self._followed = (kinematics, kinematics.placements)
            self.prepare(kinematics)
            self._reference = q.copy()
            self._renew_all(kinematics)
            lower = self._lower
            candidates = np.flatnonzero(lower < within)
        else:
            np.subtract(q, self._reference, out=moved)
            np.abs(moved, out=moved)
            if (within is self._within or _same(within, self._within)) \
                    and moved.dot(self._ones) < self._still:
                return _closer(self.measure(self._was_near), self._was_near_within)
            lower = self._lower - self._pair_reach @ moved
            candidates = np.flatnonzero(lower < within)
            if _new_pairs(candidates, self._was_near, self.size) > _MEASURED_ALONE:
                self._renew_all(kinematics)
                lower = self._lower
                candidates = np.flatnonzero(lower < within)
        measured = self.measure(candidates)
        lower[candidates] = measured.distances
        found = _closer(measured, within[candidates] if np.ndim(within) else within)
        self._follow_from(q, lower, within, found.pairs)
        return found

    def _follow_from(self, q: np.ndarray, lower: np.ndarray, within, near: np.ndarray) -> None:
        """Make ``q`` the reference configuration, with bounds ``lower`` [m] and the
        pairs ``near`` (indices) within ``within`` [m]: the others' smallest margin
        over their lever bounds the motion the fast path of :meth:`nearby` allows."""
        self._reference[:] = q
        self._lower = lower
        self._within = within
        self._was_near = near
        self._was_near_within = within[near] if np.ndim(within) else within
        margins = (lower - within) / self._levers
        margins[near] = np.inf
        self._still = float(np.min(margins, initial=np.inf))

    def distance_rows(self, nearby: Nearby, columns=slice(None)) -> np.ndarray:
        """How fast each distance of ``nearby`` changes per joint velocity (pairs x
        columns) [m/s per rad/s or m/s]: the velocity of the second closest point minus
        that of the first, along the normal, each point carried by the joint its shape
        hangs on (``nearby`` measured at the current state).

        With a joint coordinate's column of the ``WORLD`` Jacobian ``J = [v0; w]`` (``v0``
        the velocity of the moving body's point at the world's origin), a point ``p``
        moves at ``v0 + w x p``, so its speed along ``n`` is ``[n; p x n] . J``. The two
        closest points lie on one line along ``n``, so ``p x n`` is the same for both:
        one product with every coordinate's column
        (:attr:`~robocop_dsl.control.kinematics.Kinematics.joint_columns`), signed by the
        coordinates that move one shape and not the other."""
        normals = nearby.normals
        moments = (nearby.points[:, :, None] * normals[:, None, :]).reshape(-1, 9) @ _CROSS
        columns_of, select, signs, fold = self._rates_basis(nearby.pairs, columns)
        if select is not None:
            columns_of = columns_of[:, select]
        rates = np.concatenate((normals, moments), axis=1) @ columns_of
        rates *= signs
        return rates if fold is None else rates @ fold

    def _rates_basis(self, pairs: np.ndarray, columns) -> tuple:
        """What the rates of ``pairs`` are taken against, as ``(columns_of, select,
        signs, fold)``: ``columns_of`` is a view of the kinematics' joint columns that
        follows its state, restricted to ``columns`` when that is a slice and the model
        has no mimic joint; else ``select`` (``columns``, or ``None``) restricts it at
        each state. ``signs`` are the pairs' coordinate signs over the rates' columns,
        ``fold`` the fold onto ``columns`` (``None`` without mimic joints). Kept while
        the same array of pairs, the same columns and the same binding of the shapes
        come back."""
        known = self._basis_key
        if not (known and known[0] is pairs and known[1] is columns
                and known[2] is self._bound_to):
            kinematics = self._kinematics
            fold = kinematics.fold
            signs = self._pair_signs[pairs]
            if fold.shape[0] == fold.shape[1]:
                view, select = kinematics.joint_columns, columns
                if isinstance(columns, slice):
                    view, select = view[:, columns], None
                self._basis = (view, select, np.ascontiguousarray(signs[:, columns]), None)
            else:
                self._basis = (kinematics.joint_columns, None, signs,
                               np.ascontiguousarray(fold[:, columns]))
            self._basis_key = (pairs, columns, self._bound_to)
        return self._basis

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


def _new_pairs(candidates: np.ndarray, known: np.ndarray, size: int) -> int:
    """How many of ``candidates`` (pair indices) are not among ``known``, without
    numpy's set routines (whose first call imports ``numpy.ma``, tens of milliseconds)."""
    new = np.zeros(size, dtype=bool)
    new[candidates] = True
    new[known] = False
    return int(np.count_nonzero(new))


def _closer(measured: Nearby, within) -> Nearby:
    """The pairs of ``measured`` closer than ``within`` [m] (one distance, or one per
    pair of ``measured``), in its order: ``measured`` itself when all are."""
    keep = measured.distances < within
    return measured if np.count_nonzero(keep) == keep.size else measured.subset(keep)


def _by_distance(witnesses: list[Witness]) -> list[Witness]:
    """``witnesses``, closest first."""
    return sorted(witnesses, key=lambda witness: witness.distance)
