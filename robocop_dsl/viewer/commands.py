"""Meshcat commands kept in memory: the window a replay is recorded through."""

from __future__ import annotations

import umsgpack


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
