"""The enabled tasks' targets as ``visualization_msgs/MarkerArray`` (``/mission/targets``),
drawn as the viewer draws them: three arrows (x red, y green, z blue) for a pose or an
orientation, a sphere for a position or the point a gaze task looks at, and a smaller,
paler copy at the task's interpolated reference. Joint-space, velocity and force tasks
have no place in the scene.

Each message starts with a ``DELETEALL`` marker, so that it replaces the previous one
whole. The markers of one set of drawn tasks keep their bytes but for the stamps and
poses: their :class:`~.cdr.Layout` is made once per set."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from .cdr import Layout

FRAME_KINDS = ("pose", "orientation")
POINT_KINDS = ("position", "gaze")
DRAWN_KINDS = FRAME_KINDS + POINT_KINDS
ARROW, SPHERE, DELETE_ALL = 0, 2, 3
AXIS_LENGTH = 0.12          # [m] of a target's arrows
AXIS_WIDTH = 0.012          # [m]
SPHERE_DIAMETER = 0.05      # [m] of a position target
REFERENCE_SCALE = 0.6       # the reference marker's size relative to the target's
REFERENCE_ALPHA = 0.45
AXIS_COLORS = ((0.90, 0.22, 0.21), (0.26, 0.63, 0.28), (0.12, 0.53, 0.90))
POINT_COLOR = (0.99, 0.85, 0.21)
_TURNS = (np.eye(4),                                                   # arrows point along x
          np.array([[0, -1, 0, 0], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]]),   # to y
          np.array([[0, 0, -1, 0], [0, 1, 0, 0], [1, 0, 0, 0], [0, 0, 0, 1.0]]))   # to z


class TargetMarkers:
    """Encodes the ``MarkerArray`` of the enabled tasks' targets, one message at a
    time, keeping the layout of the last set of drawn markers."""

    def __init__(self):
        self._shapes: tuple | None = None
        self._layout: Layout | None = None

    def encode(self, views, time_ns: int) -> bytes:
        """The message of the task views ``views`` (:class:`~robocop_dsl.runtime.TaskView`)
        at ``time_ns`` [ns]."""
        shapes, poses = [], []
        for view in views:
            for which, value in (("target", view.target), ("reference", view.reference)):
                pose = _place(view.kind, value)
                if pose is not None:
                    shapes.append((view.name, which, view.kind in FRAME_KINDS))
                    poses += ([pose @ turn for turn in _TURNS] if view.kind in FRAME_KINDS
                              else [pose])
        if tuple(shapes) != self._shapes:
            self._shapes, self._layout = tuple(shapes), _layout(shapes)
        numbers = np.array([pin.SE3ToXYZQUAT(pin.SE3(pose)) for pose in poses]).reshape(1, -1)
        return self._layout.encode(np.array([time_ns]), numbers)[0]


def _place(kind: str, value) -> np.ndarray | None:
    """Where a target or reference is drawn (4x4, world frame), ``None`` when it has no
    place in space (no target yet, a gaze task's reference, a joint-space task)."""
    size = 0 if value is None else np.size(value)
    if kind in FRAME_KINDS and size == 16:
        return np.asarray(value, dtype=float).reshape(4, 4)
    if kind in POINT_KINDS and size in (3, 16):
        pose = np.eye(4)
        pose[:3, 3] = np.asarray(value, dtype=float).reshape(-1)[[3, 7, 11] if size == 16
                                                                 else [0, 1, 2]]
        return pose
    return None


def _layout(shapes: list) -> Layout:
    """The layout of a ``MarkerArray``: a ``DELETEALL``, then for each ``(task, target
    or reference, frame?)`` of ``shapes`` three arrows or a sphere."""
    layout = Layout()
    layout.uint32(1 + sum(3 if frame else 1 for _, _, frame in shapes))
    _marker(layout, "", 0, ARROW, (0, 0, 0), (0, 0, 0, 0), DELETE_ALL)
    for task, which, frame in shapes:
        scale, alpha = (1.0, 1.0) if which == "target" else (REFERENCE_SCALE, REFERENCE_ALPHA)
        if frame:
            size = (AXIS_LENGTH * scale, AXIS_WIDTH * scale, AXIS_WIDTH * scale)
            for axis, color in enumerate(AXIS_COLORS):
                _marker(layout, f"{task}/{which}", axis, ARROW, size, (*color, alpha))
        else:
            _marker(layout, f"{task}/{which}", 0, SPHERE, (SPHERE_DIAMETER * scale,) * 3,
                    (*POINT_COLOR, alpha))
    return layout


def _marker(layout: Layout, namespace: str, index: int, shape: int, scale, color,
            action: int = 0) -> None:
    """One ``visualization_msgs/Marker`` in the world frame; its pose is a slot, except
    for a ``DELETEALL``'s."""
    layout.stamp()
    layout.string("world")
    layout.string(namespace)
    for value in (index, shape, action):
        layout.int32(value)
    if action == DELETE_ALL:
        layout.constants((0, 0, 0, 0, 0, 0, 1))
    else:
        layout.numbers(7)                       # position, orientation (x, y, z, w)
    layout.constants(scale)
    layout.constants(color, "f")
    layout.int32(0)                             # lifetime: forever
    layout.uint32(0)
    layout.byte(0)                              # frame_locked
    layout.uint32(0)                            # points
    layout.uint32(0)                            # colors
    layout.string("")                           # texture_resource
    layout.int32(0)                             # texture: header stamp, frame, format, data
    layout.uint32(0)
    layout.string("")
    layout.string("")
    layout.uint32(0)
    layout.uint32(0)                            # uv_coordinates
    layout.string("")                           # text
    layout.string("")                           # mesh_resource
    layout.string("")                           # mesh_file: filename, data
    layout.uint32(0)
    layout.byte(0)                              # mesh_use_embedded_materials
