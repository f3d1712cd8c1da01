"""``clearance(A, B)`` in conditions: the smallest distance [m] between the collision
geometries of two sets (a body, or a joint group for every body its joints move), over
the pairs a collision check covers, at the runner's current state."""

from __future__ import annotations

import math


class Clearance:
    """Measures ``clearance(first, second)`` on a runner's kinematics; the scene is
    built on first use and the value computed once per state.

    Args:
        first: The first set.
        second: The second set.
    """

    def __init__(self, first: str, second: str):
        self.first, self.second = first, second
        self._scene = None
        self._kinematics = None
        self._stamp = -1
        self._value = math.inf

    def __call__(self, kinematics) -> float:
        """The clearance [m] at the current state of ``kinematics`` (``inf`` when no pair
        is checked; negative when two shapes overlap)."""
        from ..world.collision_scene import CollisionScene
        from ..world.collisions import checked_pairs

        if self._kinematics is not kinematics:
            world = kinematics.world
            self._scene = CollisionScene(world, checked_pairs(world, self.first, self.second))
            self._kinematics, self._stamp = kinematics, -1
        if self._stamp != kinematics.stamp:
            self._scene.place(kinematics)
            self._value = self._scene.clearance()
            self._stamp = kinematics.stamp
        return self._value
