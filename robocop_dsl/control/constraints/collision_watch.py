"""The collision pairs of every ``collision_avoidance`` constraint of one controller,
looked at in one pass per state.

The constraints of a controller share one
:class:`~robocop_dsl.world.collision_scene.CollisionScene` holding the shape pairs of
them all, each constraint's pairs one after the other. At each state, the first
constraint to ask runs the broad phase, coal, the distance rates and the damper bounds
of every pair within its constraint's influence in a few vectorised passes; each
constraint then takes its own span of the result, which needs no copy.
"""

from __future__ import annotations

import itertools
from bisect import bisect_left
from typing import NamedTuple
from weakref import WeakKeyDictionary

import numpy as np

from ...world.collision_scene import NOTHING_NEAR, CollisionScene, Nearby, Witness
from ...world.collisions import collision_geometry
from ..state import ControlState
from .velocity_damper import damper_bounds

_WATCHES: WeakKeyDictionary = WeakKeyDictionary()


def collision_watch(state: ControlState) -> CollisionWatch:
    """The watch of the controller whose state is ``state`` (made on first use)."""
    watch = _WATCHES.get(state)
    if watch is None:
        watch = _WATCHES[state] = CollisionWatch(state)
    return watch


class Near(NamedTuple):
    """What one constraint watches within its influence at one state."""

    scene: CollisionScene
    nearby: Nearby
    """Every constraint's pairs within influence."""
    span: slice
    """This constraint's part of ``nearby``."""
    rows: np.ndarray
    """How fast each distance changes per command (pairs x dofs) [m/s per rad/s or m/s]."""
    bounds: np.ndarray
    """Lower bounds of the distances' rates [m/s]."""

    @property
    def count(self) -> int:
        """Number of pairs within influence."""
        return self.span.stop - self.span.start

    @property
    def witnesses(self) -> list[Witness]:
        """The pairs as :class:`~robocop_dsl.world.collision_scene.Witness` records, one
        per row of the constraint, in order."""
        return self.scene.witnesses(self.nearby.subset(self.span))


def nothing_near(scene: CollisionScene, dofs: int) -> Near:
    """No pair within influence."""
    return Near(scene, NOTHING_NEAR, slice(0, 0), np.zeros((0, dofs)), np.zeros(0))


class CollisionWatch:
    """The pairs of a controller's collision constraints in one scene.

    Args:
        state: The controller's state.
    """

    def __init__(self, state: ControlState):
        self.state = state
        self._owners: list = []
        self._pairs: list[list[tuple[str, str]]] = []
        self.scene = CollisionScene(state.world, [])
        self._starts = [0]
        """Owner ``k``'s shape pairs are ``starts[k]`` to ``starts[k + 1]`` in the scene."""
        self._tuning = 0
        self._key: tuple | None = None
        self._within = np.zeros(0)
        self._damper = np.zeros((2, 0))
        """Per shape pair, ``damping * min_distance`` [m/s] and ``damping`` [1/s]."""
        self._stamp = -1
        self._near: dict[int, Near] = {}

    def add(self, owner, pairs: list[tuple[str, str]]) -> int:
        """Watch ``pairs`` of bodies for ``owner`` (a constraint with ``enabled``,
        ``influence``, ``min_distance`` and ``damping``); returns its number of shape
        pairs."""
        self._owners.append(owner)
        self._pairs.append(pairs)
        self._rebuild()
        return self._starts[-1] - self._starts[-2]

    def remove(self, owner) -> None:
        """Stop watching the pairs of ``owner``."""
        index = next(i for i, known in enumerate(self._owners) if known is owner)
        del self._owners[index], self._pairs[index]
        self._rebuild()

    def _rebuild(self) -> None:
        world = self.state.world
        self.scene = CollisionScene(world, [pair for pairs in self._pairs for pair in pairs])
        by_body = collision_geometry(world).by_body
        counts = [sum(len(by_body[a]) * len(by_body[b]) for a, b in pairs)
                  for pairs in self._pairs]
        self._starts = [0, *itertools.accumulate(counts)]
        self._key = None
        self._stamp = -1

    def retune(self) -> None:
        """An owner's ``influence``, ``min_distance`` or ``damping`` has changed."""
        self._tuning += 1

    def near(self, owner) -> Near:
        """The pairs ``owner`` watches within its influence at the current state."""
        kinematics = self.state.kinematics
        key = (self.state.revision, self._tuning)
        if self._stamp != kinematics.stamp or key != self._key:
            self._stamp = kinematics.stamp
            self._look(key)
        near = self._near.get(id(owner))
        return nothing_near(self.scene, self.state.dofs) if near is None else near

    def _look(self, key: tuple) -> None:
        """Every owner's pairs within influence at the current state, rows and bounds
        included; ``key`` tells whether the owners' parameters may have changed."""
        if key != self._key:
            self._key = key
            counts = np.diff(self._starts)
            self._within = np.repeat([owner.influence if owner.enabled else -np.inf
                                      for owner in self._owners], counts)
            self._damper = np.repeat([(owner.damping * owner.min_distance, owner.damping)
                                      for owner in self._owners], counts, axis=0).T.copy()
        state, scene = self.state, self.scene
        nearby = scene.nearby(state.kinematics, self._within)
        self._near = {}
        if not nearby.pairs.size:
            return
        pairs = nearby.pairs
        rows = scene.distance_rows(nearby, state.columns)
        offset, damping = self._damper[:, pairs]
        bounds = damper_bounds(offset - damping * nearby.distances, rows @ state.velocity,
                               damping, state.time_step)
        found = pairs.tolist()
        cuts = [bisect_left(found, start) for start in self._starts]
        for owner, start, end in zip(self._owners, cuts, cuts[1:]):
            if end > start:
                self._near[id(owner)] = Near(scene, nearby, slice(start, end),
                                             rows[start:end], bounds[start:end])
