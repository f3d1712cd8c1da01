"""The ``collision_avoidance`` constraint: keep the collision geometry of two sets of
bodies at least ``min_distance`` apart with a velocity damper.

For every pair of shapes closer than ``influence`` (witness points ``p1``, ``p2`` and
unit normal ``n`` from the first to the second, from coal), the distance ``d`` may
only shrink as fast as ``damping * (d - min_distance)``::

    n . (v(p2) - v(p1)) >= -damping * (d - min_distance)

with ``v(p) = J_v dq + w x (p - o)`` the velocity of the witness point carried by its
body (frame origin ``o``, Jacobians of that body). In discrete time the gap to
``min_distance`` then shrinks by at most the factor ``1 - damping * dt`` per cycle, so
it is never crossed (up to the distance's curvature over one cycle). Where the distance
is not smooth (a face parallel to another: the closest points jump from corner to
corner) the damper could ask for a velocity jump; the pair is then asked to brake to a
stop at ``min_distance`` instead. Such a face held against another rocks a little from
corner to corner and may sink below ``min_distance``; a pair closer than
``min_distance`` is pushed apart fast enough to remove the overlap in 50 ms (up to
2 cm/s, or at the damper's rate if faster), which keeps that sink to a few tenths of a
millimetre (:func:`~robocop_dsl.control.constraints.velocity_damper.damper_bounds`).

Pairs beyond ``influence`` cost almost nothing: each pair's distance is bounded from
below by what was measured last minus how far the joints have moved it since
(:meth:`~robocop_dsl.world.collision_scene.CollisionScene.nearby`; a subtraction and a
sum while the joints have moved too little for any bound to reach influence), coal
measures only the pairs whose bound falls within influence, and the constraint has rows
for those alone. The collision constraints of a controller share one scene
(:mod:`~robocop_dsl.control.constraints.collision_watch`): their pairs are measured,
their rows and damper bounds computed, in one vectorised pass per cycle. The row count
grows by four rows when a pair comes within influence and finds none free, and shrinks
when half of its rows stay unused, so that the QP is rebuilt seldom. Unused rows are
zero with infinite bounds.
"""

from __future__ import annotations

import numpy as np

from ...world.collision_scene import Witness
from ...world.collisions import checked_pairs
from ..exceptions import InvalidParameter, UnknownName
from ..parameters import scalar_parameter
from ..state import ControlState
from .base import Constraint
from .collision_watch import collision_watch

_ROW_CHUNK = 4
"""Rows are added and removed in multiples of this, to rebuild the QP seldom."""


class CollisionAvoidanceConstraint(Constraint):
    """Keeps the collision shapes of set ``first`` and set ``other`` apart.

    A set is a body, or a joint group (or joint) standing for every body its joints
    move; ``other`` defaults to ``first`` (the set against itself). Pairs of adjacent
    bodies, pairs the world allows and pairs no joint moves apart are left out
    (:func:`~robocop_dsl.world.collisions.checked_pairs`), and so are pairs that the
    controlled joints cannot move apart.

    Args:
        name: The constraint's name.
        state: The controller's state.
        first: The first set.
        other: The second set (default ``first``).
        min_distance: Smallest distance allowed between two shapes [m].
        influence: Distance below which a pair is constrained [m], above ``min_distance``.
        damping: Rate at which the gap to ``min_distance`` may close [1/s].

    Raises:
        UnknownName: a set names nothing in the world.
        InvalidParameter: a parameter out of range.
    """

    kind = "collision_avoidance"

    def __init__(self, name: str, state: ControlState, first: str, *, other: str | None = None,
                 min_distance: float = 0.01, influence: float = 0.1, damping: float = 5.0):
        super().__init__(name, state)
        world = state.world
        other = first if other is None else other
        self.first, self.other = first, other
        for subject in (first, other):
            if not (world.has_body(subject) or world.has_group(subject)
                    or subject in world.joint_names()):
                raise UnknownName("body or joint group", subject,
                                  world.body_names() + world.group_names())
        driven = {int(v) for v in state.v_indices}
        model = world.model
        pairs = [pair for pair in checked_pairs(world, first, other)
                 if any(_driven_by(model, world.body_frame_id(body), driven) for body in pair)]
        self.watch = collision_watch(state)
        self._min_distance, self._influence = 0.0, np.inf
        self.influence = influence
        self.min_distance = min_distance
        self.damping = damping
        self._pairs_checked = self.watch.add(self, pairs)
        self._seen = self.watch.seen
        self._span = (0, 0)
        self._stamp, self._written = -1, (-1, -1)
        self._wanted = 0
        self._size = 0
        self._jacobian = np.zeros((0, state.dofs))
        self._lower = np.zeros(0)
        self._upper = np.zeros(0)
        self._filled = 0
        self._target: np.ndarray | None = None
        self._target_filled = 0

    @property
    def min_distance(self) -> float:
        """Smallest distance allowed between two shapes [m]."""
        return self._min_distance

    @min_distance.setter
    def min_distance(self, value) -> None:
        value = scalar_parameter(self.label, "min_distance", value, minimum=0.0)
        if value >= self._influence:
            raise InvalidParameter(self.label, "min_distance", value,
                                   f"a distance below influence ({self._influence:g} m)")
        self._min_distance = value
        self._retuned()

    @property
    def influence(self) -> float:
        """Distance below which a pair is constrained [m]."""
        return self._influence

    @influence.setter
    def influence(self, value) -> None:
        value = scalar_parameter(self.label, "influence", value, minimum=0.0, strict=True)
        if value <= self._min_distance:
            raise InvalidParameter(self.label, "influence", value,
                                   f"a distance above min_distance ({self._min_distance:g} m)")
        self._influence = value
        self._retuned()

    @property
    def damping(self) -> float:
        """Rate at which the gap to ``min_distance`` may close [1/s]."""
        return self._damping

    @damping.setter
    def damping(self, value) -> None:
        value = scalar_parameter(self.label, "damping", value, minimum=0.0, strict=True)
        if value * self.state.time_step >= 1.0:
            raise InvalidParameter(self.label, "damping", value,
                                   f"less than 1 / time step ({1 / self.state.time_step:g} 1/s)")
        self._damping = value
        self._retuned()

    def _retuned(self) -> None:
        """A parameter has changed: the rows are written again."""
        self._stamp, self._written = -1, (-1, -1)
        self.watch.retune()

    @property
    def pairs_checked(self) -> int:
        """Number of shape pairs the constraint watches."""
        return self._pairs_checked

    @property
    def pairs_near(self) -> int:
        """Number of shape pairs within influence at the last cycle."""
        first, end = self._span
        return end - first

    @property
    def smallest_distance(self) -> float:
        """The smallest distance [m] between the constraint's shapes at the last cycle,
        over the pairs within influence (``inf`` when none is)."""
        first, end = self._span
        if end == first:
            return np.inf
        return float(self._seen.nearby.distances[first:end].min())

    @property
    def witnesses(self) -> list[Witness]:
        """The shape pairs within influence at the last cycle, in the order of the rows
        (while the QP has a row for each)."""
        return self._seen.witnesses(self._span)

    @property
    def rows(self) -> int:
        self._update(self.state)
        self._size = self._wanted
        return self._size

    def _update(self, state: ControlState) -> None:
        """Take the pairs within influence at the current state and their bounds from
        the watch (it measures once per state, and bounds again when the command or the
        acceleration limits change); decide the row count the next plan should have."""
        watch = self.watch
        span = watch.span(self)
        if self._stamp == state.kinematics.stamp and watch.seen is self._seen:
            return
        self._stamp, self._written = state.kinematics.stamp, (-1, -1)
        self._span = first, end = span
        self._seen = watch.seen
        wanted = _ROW_CHUNK * -((first - end) // _ROW_CHUNK)
        if wanted > self._size or 2 * wanted <= self._size:
            self._wanted = wanted
            if wanted != self._size:
                state.revision += 1

    def _write_rows(self, state: ControlState) -> None:
        """The rows of the pairs within influence in :attr:`rows` rows of the
        constraint's own arrays (for :meth:`compute_jacobian` and :meth:`compute_bounds`)."""
        self._update(state)
        if self._written == (self._stamp, self._size):
            return
        size = self._size
        if self._jacobian.shape[0] != size:
            self._jacobian = np.zeros((size, state.dofs))
            self._lower = np.full(size, -np.inf)
            self._upper = np.full(size, np.inf)
            self._filled = 0
        self._written = (self._stamp, size)
        self._filled = self._fill(self._jacobian, self._lower, self._filled)

    def write_rows(self, state: ControlState, jacobian: np.ndarray, lower: np.ndarray,
                   upper: np.ndarray) -> None:
        """The rows straight into the QP's arrays; only the rows that held pairs and no
        longer do are cleared."""
        self._update(state)
        if jacobian is not self._target:
            self._target, self._target_filled = jacobian, len(lower)
            upper[:] = np.inf
        self._target_filled = self._fill(jacobian, lower, self._target_filled)

    def _fill(self, jacobian: np.ndarray, lower: np.ndarray, filled: int) -> int:
        """Write the pairs within influence into ``jacobian`` and ``lower``, the rows
        after them zero and ``-inf`` (``filled`` rows held pairs before); returns how
        many rows hold pairs now. With more pairs than rows (until the QP grows at the
        next cycle), the closest pairs get the rows."""
        first, end = self._span
        count = end - first
        seen = self._seen
        if count > lower.shape[0]:
            count = lower.shape[0]
            closest = first + np.argsort(seen.nearby.distances[first:end], kind="stable")
            jacobian[:] = seen.rows[closest[:count]]
            lower[:] = seen.bounds[closest[:count]]
            return count
        if count < filled:
            jacobian[count:filled] = 0.0
            lower[count:filled] = -np.inf
        if count:
            jacobian[:count] = seen.rows[first:end]
            lower[:count] = seen.bounds[first:end]
        return count

    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        self._write_rows(state)
        return self._jacobian

    def compute_bounds(self, state: ControlState) -> tuple[np.ndarray, np.ndarray]:
        self._write_rows(state)
        return self._lower, self._upper

    def parameters(self) -> dict:
        return {"other": self.other, "min_distance": self._min_distance,
                "influence": self._influence, "damping": self._damping}

    def release(self) -> None:
        self.watch.remove(self)

    def configure(self, **parameters) -> None:
        allowed = ["min_distance", "influence", "damping"]
        unknown = set(parameters) - set(allowed)
        if unknown:
            raise UnknownName("parameter of collision_avoidance", sorted(unknown)[0], allowed)
        super().configure(**parameters)

    def describe(self) -> str:
        return f"first={self.first!r}, "


def _driven_by(model, frame: int, columns: set) -> bool:
    """Whether one of the velocity coordinates ``columns`` moves frame ``frame`` (a
    mimic joint moving with its primary's coordinate)."""
    joint = model.frames[frame].parentJoint
    while joint > 0:
        start = model.joints[joint].idx_v
        if any(v in columns for v in range(start, start + model.nvExtendeds[joint])):
            return True
        joint = model.parents[joint]
    return False
