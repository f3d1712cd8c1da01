"""Rigid placements as URDF writes them: ``xyz`` in metres and ``rpy`` in radians,
with R = Rz(yaw) Ry(pitch) Rx(roll). The loader composes them without pinocchio, which
``check`` never imports."""

from __future__ import annotations

import math

import numpy as np

IDENTITY = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))


def rotation(rpy) -> np.ndarray:
    """3x3 rotation matrix of roll, pitch, yaw [rad]."""
    roll, pitch, yaw = rpy
    cr, sr, cp, sp = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def rpy_of(matrix: np.ndarray) -> tuple:
    """Roll, pitch, yaw [rad] of a rotation matrix (pitch in [-pi/2, pi/2])."""
    pitch = math.atan2(-matrix[2, 0], math.hypot(matrix[0, 0], matrix[1, 0]))
    if math.isclose(abs(pitch), math.pi / 2, abs_tol=1e-9):
        yaw = math.atan2(-matrix[0, 1], matrix[1, 1])
        return (0.0, pitch, yaw)
    return (math.atan2(matrix[2, 1], matrix[2, 2]), pitch,
            math.atan2(matrix[1, 0], matrix[0, 0]))


def compose(first: tuple, second: tuple) -> tuple:
    """The ``(xyz, rpy)`` placement of ``second`` expressed after ``first``."""
    (p1, r1), (p2, r2) = first, second
    turn = rotation(r1)
    xyz = np.asarray(p1, float) + turn @ np.asarray(p2, float)
    return tuple(map(float, xyz)), tuple(map(float, rpy_of(turn @ rotation(r2))))
