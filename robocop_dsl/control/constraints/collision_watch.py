"""The collision pairs of every ``collision_avoidance`` constraint of one controller,
looked at in one pass per state.

The constraints of a controller share one
:class:`~robocop_dsl.world.collision_scene.CollisionScene` holding the shape pairs of
them all, each constraint's pairs one after the other. At each state, the first
constraint to ask runs the broad phase, coal, the distance rates and the damper bounds
of every pair within its constraint's influence in a few vectorised passes (the
damper's bound met with the viable bound of
:func:`~robocop_dsl.safety.viable.distance_rate_bounds`); each
constraint then takes its own span of the result. While the same pairs stay within
influence, what depends on them alone (each constraint's span, the damper's parameters)
is kept from cycle to cycle.
"""

from __future__ import annotations

import itertools
from bisect import bisect_left
from typing import NamedTuple

import numpy as np

from ...world.collision_scene import NOTHING_NEAR, CollisionScene, Nearby, Witness
from ...world.collisions import collision_geometry
from ...safety.viable import distance_rate_bounds
from ..state import ControlState
from .velocity_damper import damper_bounds

_NO_SPAN = (0, 0)


def collision_watch(state: ControlState) -> CollisionWatch:
    """The watch of the controller whose state is ``state`` (made on first use, kept
    by the state: it lives as long as the controller)."""
    if state.collision_watch is None:
        state.collision_watch = CollisionWatch(state)
    return state.collision_watch


class Seen(NamedTuple):
    """Every watched pair within its constraint's influence at one state."""

    scene: CollisionScene
    nearby: Nearby
    """The pairs, each constraint's one after the other."""
    rows: np.ndarray
    """How fast each distance changes per command (pairs x dofs) [m/s per rad/s or m/s]."""
    bounds: np.ndarray
    """Lower bounds of the distances' rates [m/s]."""

    def witnesses(self, span: tuple[int, int]) -> list[Witness]:
        """The pairs ``span`` (first, end) as
        :class:`~robocop_dsl.world.collision_scene.Witness` records, in order."""
        return self.scene.witnesses(self.nearby.subset(slice(*span)))


def nothing_seen(scene: CollisionScene, dofs: int) -> Seen:
    """No pair within influence."""
    return Seen(scene, NOTHING_NEAR, np.zeros((0, dofs)), np.zeros(0))


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
        self._spans: dict = {}
        self._spans_of = b""
        """The pairs (as bytes) the spans and damper parameters were taken for."""
        self._offset = self._damping = np.zeros(0)
        self._nothing = self.seen = nothing_seen(self.scene, state.dofs)
        """What the last look at a state found."""
        self._found: tuple | None = None
        """The pairs within influence, their rows and damper offsets [m/s]."""
        self._bounded_for: tuple = (None, None, b"")
        """The velocity and acceleration limits :attr:`seen`'s bounds were computed with
        (the arrays, and their values as bytes)."""

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
        self.scene.prepare(self.state.kinematics)
        by_body = collision_geometry(world).by_body
        counts = [sum(len(by_body[a]) * len(by_body[b]) for a, b in pairs)
                  for pairs in self._pairs]
        self._starts = [0, *itertools.accumulate(counts)]
        self._key = None
        self._stamp = -1
        self._found = None
        self._nothing = self.seen = nothing_seen(self.scene, self.state.dofs)

    def retune(self) -> None:
        """An owner's ``influence``, ``min_distance`` or ``damping`` has changed."""
        self._tuning += 1

    def span(self, owner) -> tuple[int, int]:
        """The part of :attr:`seen` that holds the pairs ``owner`` watches within its
        influence at the current state: ``(first, end)``."""
        stamp = self.state.kinematics.stamp
        key = (self._tuning, *[owner.enabled for owner in self._owners])
        if self._stamp != stamp or self._key != key:
            self._stamp = stamp
            self._look(key)
        elif self._motion_changed():
            self._bound()
        return self._spans.get(owner, _NO_SPAN)

    def _motion_changed(self) -> bool:
        """Whether the state's velocity or acceleration limits are not those the bounds
        were computed with (the configuration can stay while they change: a new
        command, a new table of limits)."""
        state = self.state
        velocity, acceleration, values = self._bounded_for
        if state.velocity is velocity and state.max_acceleration is acceleration:
            return False
        return state.velocity.tobytes() + state.max_acceleration.tobytes() != values

    def _look(self, key: tuple) -> None:
        """Every owner's pairs within influence at the current state, rows and bounds
        included; ``key`` (the tuning count and whether each owner is enabled) tells
        whether the owners' parameters may have changed."""
        if key != self._key:
            self._key = key
            self._spans_of = b""
            counts = np.diff(self._starts)
            self._within = np.repeat([owner.influence if owner.enabled else -np.inf
                                      for owner in self._owners], counts)
            self._damper = np.repeat([(owner.damping * owner.min_distance, owner.damping)
                                      for owner in self._owners], counts, axis=0).T.copy()
        state, scene = self.state, self.scene
        nearby = scene.nearby(state.kinematics, self._within)
        pairs = nearby.pairs
        if not pairs.size:
            self.seen, self._spans, self._spans_of = self._nothing, {}, b""
            self._found = None
            return
        signature = pairs.tobytes()
        if signature != self._spans_of:
            self._spans_of = signature
            self._offset, self._damping = self._damper[:, pairs]
            found = pairs.tolist()
            cuts = [bisect_left(found, start) for start in self._starts]
            self._spans = {owner: (start, end) for owner, start, end
                           in zip(self._owners, cuts, cuts[1:]) if end > start}
        self._found = (nearby, scene.distance_rows(nearby, state.columns),
                       self._offset - self._damping * nearby.distances)
        self._bound()

    def _bound(self) -> None:
        """The damper and viable bounds of the pairs found, at the state's velocity and
        acceleration limits."""
        state = self.state
        self._bounded_for = (state.velocity, state.max_acceleration,
                             state.velocity.tobytes() + state.max_acceleration.tobytes())
        if self._found is None:
            return
        nearby, rows, damper = self._found
        rate = rows @ state.velocity
        bounds = damper_bounds(damper, rate, self._damping, state.time_step)
        viable = distance_rate_bounds(damper / -self._damping, rows, rate,
                                      state.max_acceleration, state.time_step)
        self.seen = Seen(self.scene, nearby, rows, np.maximum(bounds, viable, out=viable))
