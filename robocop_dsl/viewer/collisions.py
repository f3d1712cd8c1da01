"""Collision avoidance as drawn in the scene: for each pair of shapes within a
``collision_avoidance`` constraint's influence, a line between the witness points,
coloured by how close the pair is (red at ``min_distance``, yellow near ``influence``).

The lines are computed from each drawn record's configuration on a copy of the world,
in the viewer's thread (live) or when the replay is written, never in the control loop.
A line is a unit cylinder stretched to its length: its node gets a rigid pose and a
scale, and one child per colour band, of which the band of the pair is visible.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

ROOT = "collisions"
SLOTS = 12                  # lines drawn at most: the closest pairs
RADIUS = 0.003              # [m]
BANDS = (0xE53935, 0xFB8C00, 0xFDD835)
"""Colours from the closest third of the range [min_distance, influence] outwards."""


@dataclass(frozen=True)
class Watched:
    """The pairs of one collision constraint and its distances [m]."""

    scene: object
    min_distance: float
    influence: float


@dataclass
class Lines:
    """One record's lines: node path -> rigid 4x4 pose [m] and stretch along the line
    (scale ``[1, length, 1]``), and band path -> visibility."""

    poses: dict
    scales: dict
    visible: dict

    def transforms(self) -> dict:
        """Node path -> 4x4 matrix with the stretch (for a live scene)."""
        return {path: pose @ np.diag([*self.scales[path], 1.0])
                for path, pose in self.poses.items()}


def slot_path(slot: int) -> str:
    return f"{ROOT}/{slot}"


def band_path(slot: int, band: int) -> str:
    return f"{ROOT}/{slot}/{band}"


class CollisionLines:
    """The lines of a run's collision constraints.

    Args:
        world: The run's world (a copy of its model is used).
        constraints: ``(first, other, min_distance, influence)`` of each constraint.
    """

    def __init__(self, world, constraints: list[tuple[str, str, float, float]]):
        from ..control.kinematics import Kinematics
        from ..world.collision_scene import CollisionScene
        from ..world.collisions import checked_pairs

        self.world = world.copy()
        self.kinematics = Kinematics(self.world)
        self.watched = [Watched(CollisionScene(self.world, checked_pairs(self.world, a, b)),
                                low, high) for a, b, low, high in constraints]

    @classmethod
    def of_runner(cls, runner) -> "CollisionLines | None":
        """The lines of the enabled-or-not collision constraints of a runner's
        controller; ``None`` when it has none."""
        found = [(c.first, c.other, c.min_distance, c.influence)
                 for c in runner.controller.constraints() if c.kind == "collision_avoidance"]
        return cls(runner.kinematics.world, found) if found else None

    def load(self, visualizer) -> None:
        """Send the line nodes, hidden."""
        import meshcat.geometry as mg

        for slot in range(SLOTS):
            for band, color in enumerate(BANDS):
                node = visualizer[band_path(slot, band)]
                node.set_object(mg.Cylinder(1.0, RADIUS), mg.MeshBasicMaterial(color=color))
                node.set_property("visible", False)

    def lines(self, q: np.ndarray) -> Lines:
        """The lines at configuration ``q`` (the whole world's)."""
        self.kinematics.update(np.asarray(q, dtype=float))
        found = []
        for watched in self.watched:
            watched.scene.place(self.kinematics)
            span = watched.influence - watched.min_distance
            for witness in watched.scene.closest(watched.influence):
                closeness = (witness.distance - watched.min_distance) / span
                band = min(len(BANDS) - 1, max(0, int(closeness * len(BANDS))))
                found.append((witness.distance, band, witness))
        found.sort(key=lambda item: item[0])
        poses, scales, visible = {}, {}, {}
        for slot in range(SLOTS):
            shown = found[slot] if slot < len(found) else None
            for band in range(len(BANDS)):
                visible[band_path(slot, band)] = shown is not None and shown[1] == band
            if shown is not None:
                witness = shown[2]
                poses[slot_path(slot)], length = _segment(witness.point_first,
                                                          witness.point_second)
                scales[slot_path(slot)] = [1.0, length, 1.0]
        return Lines(poses, scales, visible)


def _segment(start: np.ndarray, end: np.ndarray) -> tuple[np.ndarray, float]:
    """The rigid pose taking a meshcat cylinder (along y, centred) onto the segment,
    and the segment's length [m]."""
    direction = end - start
    length = float(np.linalg.norm(direction))
    pose = np.eye(4)
    pose[:3, 3] = (start + end) / 2
    if length > 1e-12:
        y = direction / length
        helper = np.array([1.0, 0, 0]) if abs(y[0]) < 0.9 else np.array([0, 0, 1.0])
        x = np.cross(y, helper)
        x /= np.linalg.norm(x)
        pose[:3, :3] = np.column_stack((x, y, np.cross(x, y)))
    return pose, max(length, 1e-6)
