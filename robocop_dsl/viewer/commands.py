"""Meshcat commands kept in memory: the window a replay is recorded through."""

from __future__ import annotations

import struct

import numpy as np
import umsgpack

_FLOAT64 = 0xCB
_MATRIX = struct.Struct(">" + "Bd" * 16)


class CommandLog:
    """A Meshcat window that keeps each command, lowered to plain data, in order.

    It stands in for a server connection wherever meshcat or pinocchio expect a
    window (``meshcat.Visualizer(window=CommandLog())``).
    """

    def __init__(self):
        self.commands: list[dict] = []

    def send(self, command) -> None:
        """Keep ``command`` (a meshcat command object) as its lowered dictionary."""
        self.commands.append(command.lower())


def pack(command: dict) -> bytes:
    """The msgpack bytes the Meshcat browser client decodes for one lowered command."""
    return umsgpack.packb(command)


def unpack(data: bytes) -> dict:
    """The lowered command encoded in ``data`` (inverse of :func:`pack`)."""
    return umsgpack.unpackb(data)


def pack_transform(path: str, matrix: np.ndarray) -> bytes:
    """The bytes of ``meshcat``'s ``SetTransform(matrix, path)``, lowered and packed, in
    a few microseconds (the pure-Python packer takes tens, on the publisher's every
    message).

    Args:
        path: The node's full Meshcat path, e.g. ``/meshcat/world/visuals/workbench``.
        matrix: 4x4 homogeneous transform [m].
    """
    values = np.asarray(matrix, dtype=float).T.ravel().tolist()
    floats = _MATRIX.pack(*[item for value in values for item in (_FLOAT64, value)])
    return (b"\x83" + _pack_text("type") + _pack_text("set_transform") + _pack_text("path")
            + _pack_text(path) + _pack_text("matrix") + b"\xdc\x00\x10" + floats)


def _pack_text(text: str) -> bytes:
    data = text.encode("utf-8")
    if len(data) < 32:
        return bytes([0xA0 | len(data)]) + data
    if len(data) < 256:
        return bytes([0xD9, len(data)]) + data
    return b"\xda" + struct.pack(">H", len(data)) + data
