"""The camera's starting view, set with plain Meshcat commands.

Meshcat's default camera sits at ``/Cameras/default/rotated/<object>``, where
``rotated`` turns three.js's y-up convention into the world's z-up one, and its orbit
controls always look at the viewer's origin (meshcat 0.3.2 has no command to move that
target). So the view is centred by shifting the drawn world instead: the scene root
``/meshcat``, the floor grid and the world axes are translated by ``-centre``, and the
camera is placed relative to the centre. Orbiting then turns around the centre."""

from __future__ import annotations

import math

import numpy as np

CAMERA = "/Cameras/default/rotated/<object>"
SHIFTED = ("/meshcat", "/Grid", "/Axes")
FIELD_OF_VIEW = math.radians(75)        # meshcat's default vertical field of view
VIEW_DIRECTION = np.array([1.0, -0.75, 0.55])   # from the scene towards the camera
MARGIN = 0.9


def camera_view(lower: np.ndarray, upper: np.ndarray) -> tuple:
    """Centre and camera position [m, world frame] that frame a box.

    Args:
        lower: Lower corner of the box to frame [m].
        upper: Upper corner [m].

    Returns:
        ``(centre, position)``: the camera looks at ``centre`` from ``position``, in
        front of the robot (+x), to its right and above, far enough for the box's
        bounding sphere to fit the vertical field of view.
    """
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    centre = (lower + upper) / 2
    radius = np.linalg.norm(upper - lower) / 2
    distance = MARGIN * radius / math.sin(FIELD_OF_VIEW / 2)
    direction = VIEW_DIRECTION / np.linalg.norm(VIEW_DIRECTION)
    return centre, centre + distance * direction


def set_camera(visualizer, centre: np.ndarray, position: np.ndarray) -> None:
    """Look at ``centre`` from ``position`` [m, world frame]."""
    shift = np.eye(4)
    shift[:3, 3] = -np.asarray(centre, float)
    for path in SHIFTED:
        visualizer[path].set_transform(shift)
    x, y, z = np.asarray(position, float) - np.asarray(centre, float)
    visualizer[CAMERA].set_property("position", [float(x), float(z), float(-y)])
