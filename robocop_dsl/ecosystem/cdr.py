"""CDR, the encoding of ROS 2 messages: little endian, each number aligned to its size
from the start of the message, after a 4-byte encapsulation header.

The messages a run publishes every cycle (joint states, transforms, wrenches) have the
same strings and array lengths all run long: a :class:`Layout` is their bytes with the
changing numbers left blank, so that a batch of them is a few numpy copies. The other
messages are encoded from dictionaries by mcap-ros2-support's encoder
(:func:`encoder`), which tests also hold the layouts to, byte for byte.
"""

from __future__ import annotations

import struct

import numpy as np

from .msgdefs import message_definition

ENCAPSULATION = b"\x00\x01\x00\x00"     # CDR, little endian
_UINT32 = struct.Struct("<I")
_INT32 = struct.Struct("<i")


class Layout:
    """One message's bytes, built field by field in the message's order; ``stamp`` and
    ``numbers`` leave slots that :meth:`encode` fills for each message of a batch."""

    def __init__(self):
        self._bytes = bytearray(ENCAPSULATION)
        self._stamps: list = []
        self._numbers: list = []

    def stamp(self) -> None:
        """A ``builtin_interfaces/Time`` slot."""
        self._align(4)
        self._stamps.extend(range(len(self._bytes), len(self._bytes) + 8))
        self._bytes += bytes(8)

    def string(self, text: str) -> None:
        data = text.encode("utf-8") + b"\0"
        self.uint32(len(data))
        self._bytes += data

    def strings(self, texts: list) -> None:
        """A ``string[]`` of fixed content."""
        self.uint32(len(texts))
        for text in texts:
            self.string(text)

    def uint32(self, value: int) -> None:
        """A ``uint32`` of fixed value (a sequence's length, a time's nanoseconds)."""
        self._align(4)
        self._bytes += _UINT32.pack(value)

    def int32(self, value: int) -> None:
        self._align(4)
        self._bytes += _INT32.pack(value)

    def byte(self, value: int) -> None:
        """A ``bool``, ``byte`` or ``uint8`` of fixed value."""
        self._bytes.append(value)

    def constants(self, values, kind: str = "d") -> None:
        """Numbers of fixed value: ``float64`` (``kind`` ``d``) or ``float32`` (``f``)."""
        size = struct.calcsize(kind)
        for value in values:
            self._align(size)
            self._bytes += struct.pack("<" + kind, value)

    def numbers(self, count: int) -> None:
        """``count`` consecutive ``float64`` slots."""
        if count:
            self._align(8)
            self._numbers.extend(range(len(self._bytes), len(self._bytes) + 8 * count))
            self._bytes += bytes(8 * count)

    def sequence(self, count: int) -> None:
        """A ``float64[]`` of ``count`` slots."""
        self.uint32(count)
        self.numbers(count)

    def encode(self, stamps: np.ndarray, numbers: np.ndarray) -> list:
        """One message per row: every stamp slot at ``stamps[i]`` [ns], the number
        slots, in the order they were laid out, from ``numbers[i]``."""
        stamps = np.asarray(stamps, dtype=np.int64)
        rows = len(stamps)
        out = np.empty((rows, len(self._bytes)), np.uint8)
        out[:] = np.frombuffer(bytes(self._bytes), np.uint8)
        if self._stamps:
            time = np.empty((rows, 2), "<u4")
            time[:, 0] = (stamps // 1_000_000_000).astype("<i4").view("<u4")
            time[:, 1] = stamps % 1_000_000_000
            slots = len(self._stamps) // 8
            out[:, self._stamps] = np.broadcast_to(
                time.view(np.uint8)[:, None, :], (rows, slots, 8)).reshape(rows, -1)
        if self._numbers:
            values = np.ascontiguousarray(numbers, dtype="<f8").reshape(rows, -1)
            out[:, self._numbers] = values.view(np.uint8)
        return [row.tobytes() for row in out]

    def _align(self, size: int) -> None:
        self._bytes += bytes(-(len(self._bytes) - len(ENCAPSULATION)) % size)


def encoder(type_name: str):
    """mcap-ros2-support's CDR encoder of ``type_name`` (``pkg/msg/Type``): a function
    from a dictionary of the message's fields to its bytes."""
    from mcap_ros2._dynamic import serialize_dynamic

    return serialize_dynamic(type_name, message_definition(type_name))[type_name]


def stamp(time_ns: int) -> dict:
    """A ``builtin_interfaces/Time`` of ``time_ns`` [ns]."""
    seconds, nanoseconds = divmod(int(time_ns), 1_000_000_000)
    return {"sec": seconds, "nanosec": nanoseconds}
