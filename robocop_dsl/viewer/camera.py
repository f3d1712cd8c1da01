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
ASPECT = 4 / 3                          # narrowest page shape framed (width / height)
VIEW_DIRECTION = np.array([1.0, 0.7, 0.5])      # from the scene towards the camera
MARGIN = 1.1                            # view size / scene size, on the tighter side


def camera_view(points: np.ndarray) -> tuple:
    """Centre and camera position [m, world frame] that frame a set of points.

    Args:
        points: ``N x 3`` points to keep in view [m], e.g. the corners of the bodies.

    Returns:
        ``(centre, position)``: the camera looks at the centre of the points' box from
        in front of the robot (+x), to its left and above, just far enough for every
        point to fit in a page of shape ``ASPECT`` with a ``MARGIN``.
    """
    points = np.asarray(points, float)
    centre = (points.min(axis=0) + points.max(axis=0)) / 2
    back = VIEW_DIRECTION / np.linalg.norm(VIEW_DIRECTION)
    right = np.cross(-back, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, -back)
    vertical = math.tan(FIELD_OF_VIEW / 2) / MARGIN
    horizontal = vertical * ASPECT
    offsets = points - centre
    needed = np.maximum(np.abs(offsets @ up) / vertical, np.abs(offsets @ right) / horizontal)
    distance = float(np.max(offsets @ back + needed))
    return centre, centre + distance * back


def set_camera(visualizer, centre: np.ndarray, position: np.ndarray) -> None:
    """Look at ``centre`` from ``position`` [m, world frame]."""
    shift = np.eye(4)
    shift[:3, 3] = -np.asarray(centre, float)
    for path in SHIFTED:
        visualizer[path].set_transform(shift)
    x, y, z = np.asarray(position, float) - np.asarray(centre, float)
    visualizer[CAMERA].set_property("position", [float(x), float(z), float(-y)])
