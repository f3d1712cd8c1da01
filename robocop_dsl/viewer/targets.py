"""Task targets as drawn in the scene: a frame triad for pose and orientation targets,
a sphere for position targets and for the point a gaze task looks at, and a smaller,
paler copy (the ghost) at the task's interpolated reference when it is a place in space.
Joint-space and velocity tasks have no place in the scene."""

from __future__ import annotations

import numpy as np

ROOT = "targets"
FRAME_KINDS = ("pose", "orientation")
POINT_KINDS = ("position", "gaze")
DRAWN_KINDS = FRAME_KINDS + POINT_KINDS
TARGET, REFERENCE = "target", "reference"

AXIS_LENGTH = 0.12          # [m] of a target triad's axes
AXIS_RADIUS = 0.006         # [m]
SPHERE_RADIUS = 0.025       # [m] of a position target
GHOST_SCALE = 0.6           # size of the reference marker relative to the target's
GHOST_OPACITY = 0.45
AXIS_COLORS = {"x": 0xE53935, "y": 0x43A047, "z": 0x1E88E5}
POINT_COLOR = 0xFDD835


def marker_path(task: str, which: str) -> str:
    """Meshcat path of a task's ``target`` or ``reference`` marker."""
    return f"{ROOT}/{task}/{which}"


def is_drawn(task) -> bool:
    """Whether a task (a :class:`~robocop_dsl.runtime.records.TaskView`) has a marker."""
    return task.kind in DRAWN_KINDS


def load_markers(visualizer, task: str, kind: str) -> None:
    """Send the target and reference markers of one task, hidden until it is enabled.

    Args:
        visualizer: A ``meshcat.Visualizer`` (root path).
        task: The task's name.
        kind: ``pose``, ``orientation``, ``position`` or ``gaze``.
    """
    for which, scale, opacity in ((TARGET, 1.0, 1.0), (REFERENCE, GHOST_SCALE, GHOST_OPACITY)):
        node = visualizer[marker_path(task, which)]
        if kind in FRAME_KINDS:
            _load_triad(node, scale, opacity)
        else:
            _load_sphere(node, scale, opacity)
        node.set_property("visible", False)


def _load_triad(node, scale: float, opacity: float) -> None:
    import meshcat.geometry as mg

    length, radius = AXIS_LENGTH * scale, AXIS_RADIUS * scale
    # meshcat cylinders lie along their y axis, centred on the origin
    turns = {"x": _rotation_z(-np.pi / 2), "y": np.eye(4), "z": _rotation_x(np.pi / 2)}
    for axis, turn in turns.items():
        shift = np.eye(4)
        shift[:3, 3] = {"x": (1, 0, 0), "y": (0, 1, 0), "z": (0, 0, 1)}[axis]
        shift[:3, 3] *= length / 2
        material = mg.MeshLambertMaterial(color=AXIS_COLORS[axis], opacity=opacity)
        node[axis].set_object(mg.Cylinder(length, radius), material)
        node[axis].set_transform(shift @ turn)


def _load_sphere(node, scale: float, opacity: float) -> None:
    import meshcat.geometry as mg

    material = mg.MeshLambertMaterial(color=POINT_COLOR, opacity=opacity)
    node.set_object(mg.Sphere(SPHERE_RADIUS * scale), material)


def marker_poses(task, body_position) -> dict:
    """Where a task's markers go.

    Args:
        task: A :class:`~robocop_dsl.runtime.records.TaskView` of a drawn kind: its
            target and reference are 4x4 poses for frames, 3-vectors [m] or 4x4 poses
            (their origin) for points.
        body_position: Callable giving a body's current position [m]; an orientation
            target is drawn at its body's position.

    Returns:
        Marker path -> 4x4 world pose [m]; a marker without a place in space (no target
        yet, a gaze task's reference) is left out.
    """
    poses = {}
    for which, value in ((TARGET, task.target), (REFERENCE, task.reference)):
        size = 0 if value is None else np.size(value)
        pose = np.eye(4)
        if size == 16:
            pose = np.asarray(value, dtype=float).reshape(4, 4).copy()
            if task.kind in POINT_KINDS:
                pose[:3, :3] = np.eye(3)
            elif task.kind == "orientation" and task.body is not None:
                pose[:3, 3] = body_position(task.body)
        elif size == 3 and task.kind in POINT_KINDS:
            pose[:3, 3] = np.asarray(value, dtype=float)
        else:
            continue
        poses[marker_path(task.name, which)] = pose
    return poses


def _rotation_x(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def _rotation_z(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])
