"""The loopback robot protocol: binary frames over one TCP connection on 127.0.0.1.

Every frame is a 24-byte header followed by a payload, all little-endian (see
``docs/driver_protocol.md``)::

    magic "RC" | version u8 | kind u8 | payload length u32 | sequence u64 | time f64

Kinds: ``HELLO`` (robot -> driver, once, on connection), ``STATE`` (robot -> driver,
every robot cycle), ``COMMAND`` (driver -> robot, every controller cycle). A robot with
force sensors names their bodies in its ``HELLO`` and appends one wrench per sensor to
each ``STATE``; one without sends neither.
"""

from __future__ import annotations

import select
import socket
import struct
from dataclasses import dataclass

import numpy as np

from ..diagnostics import RobocopError

MAGIC = b"RC"
VERSION = 1
HELLO, STATE, COMMAND = 1, 2, 3
HEADER = struct.Struct("<2sBBIQd")
_HELLO_FIELDS = struct.Struct("<HHd")
_MAX_PAYLOAD = 1 << 20
HOST = "127.0.0.1"
WRENCH = 6
"""Numbers of a wrench: force [N] then torque [N m], x, y, z."""


class ProtocolError(RobocopError):
    """A frame that does not follow the protocol."""


@dataclass(frozen=True)
class Message:
    """One frame: its kind, the sender's sequence number, the sender's time [s] and
    the raw payload."""

    kind: int
    sequence: int
    time: float
    payload: bytes


@dataclass(frozen=True)
class Hello:
    """What the robot says about itself on connection.

    Attributes:
        nq: Number of configuration coordinates of its joints.
        nv: Number of joint velocities (dofs).
        period: Its cycle [s].
        joints: Joint names, in coordinate order.
        sensors: The bodies of its force sensors, in the order of the wrenches of each
            ``STATE`` (none: its states carry no wrench).
    """

    nq: int
    nv: int
    period: float
    joints: tuple
    sensors: tuple = ()


def encode(kind: int, sequence: int, time: float, payload: bytes) -> bytes:
    """One frame as bytes."""
    return HEADER.pack(MAGIC, VERSION, kind, len(payload), sequence, time) + payload


def hello_payload(hello: Hello) -> bytes:
    names = "\n".join(hello.joints)
    if hello.sensors:
        names += "\0" + "\n".join(hello.sensors)
    return _HELLO_FIELDS.pack(hello.nq, hello.nv, hello.period) + names.encode("utf-8")


def decode_hello(message: Message) -> Hello:
    nq, nv, period = _HELLO_FIELDS.unpack_from(message.payload)
    text = message.payload[_HELLO_FIELDS.size:].decode("utf-8")
    joints, _, sensors = text.partition("\0")
    return Hello(nq, nv, period, tuple(joints.split("\n")) if joints else (),
                 tuple(sensors.split("\n")) if sensors else ())


def state_payload(position: np.ndarray, velocity: np.ndarray, holding: bool,
                  wrenches=()) -> bytes:
    """A STATE's payload; ``wrenches``: one ``[fx, fy, fz, tx, ty, tz]`` [N, N m] per
    force sensor the robot announced."""
    return (np.asarray(position, "<f8").tobytes() + np.asarray(velocity, "<f8").tobytes()
            + bytes([1 if holding else 0]) + np.asarray(wrenches, "<f8").tobytes())


def decode_state(message: Message, nq: int, nv: int, sensors: int = 0) -> tuple:
    """``(position (nq) [rad or m], velocity (nv) [rad/s or m/s], holding)`` of a STATE
    from a robot that announced ``sensors`` force sensors."""
    expected = 8 * (nq + nv) + 1 + 8 * WRENCH * sensors
    if len(message.payload) != expected:
        raise ProtocolError(f"STATE payload has {len(message.payload)} bytes, "
                            f"expected {expected}")
    values = np.frombuffer(message.payload, "<f8", nq + nv).astype(float)
    return values[:nq], values[nq:], bool(message.payload[8 * (nq + nv)])


def decode_wrenches(message: Message, nq: int, nv: int, sensors: int) -> np.ndarray:
    """The wrenches (``sensors`` x 6) [N, N m] of a STATE that :func:`decode_state`
    accepted: one per announced force sensor, what its body exerts on the environment,
    world frame, torque about the body's origin."""
    start = 8 * (nq + nv) + 1
    return np.frombuffer(message.payload, "<f8", WRENCH * sensors,
                         start).astype(float).reshape(sensors, WRENCH)


def command_payload(velocity: np.ndarray) -> bytes:
    return np.asarray(velocity, "<f8").tobytes()


def decode_command(message: Message, nv: int) -> np.ndarray:
    """The commanded velocity (nv) [rad/s or m/s]."""
    if len(message.payload) != 8 * nv:
        raise ProtocolError(f"COMMAND payload has {len(message.payload)} bytes, "
                            f"expected {8 * nv}")
    return np.frombuffer(message.payload, "<f8").astype(float)


class Connection:
    """Frames over a connected TCP socket.

    Args:
        sock: The socket; ``TCP_NODELAY`` is set on it.
    """

    def __init__(self, sock: socket.socket):
        self.sock = sock
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self._buffer = bytearray()

    def send(self, kind: int, sequence: int, time: float, payload: bytes) -> None:
        """Send one frame (blocks at most the socket's timeout)."""
        self.sock.sendall(encode(kind, sequence, time, payload))

    def receive(self) -> Message:
        """The next frame, waiting at most the socket's timeout.

        Raises:
            ConnectionError: The peer closed the connection.
            TimeoutError: Nothing complete arrived in time.
            ProtocolError: Bad magic, version or length.
        """
        while True:
            message = self._take()
            if message is not None:
                return message
            self._fill()

    def poll(self) -> list:
        """Every complete frame already received, without waiting.

        Raises:
            ConnectionError: The peer closed the connection.
            ProtocolError: Bad magic, version or length.
        """
        if select.select([self.sock], [], [], 0)[0]:
            self._fill()
        messages = []
        while (message := self._take()) is not None:
            messages.append(message)
        return messages

    def close(self) -> None:
        self.sock.close()

    def _fill(self) -> None:
        chunk = self.sock.recv(65536)
        if not chunk:
            raise ConnectionError("connection closed by the peer")
        self._buffer += chunk

    def _take(self) -> Message | None:
        if len(self._buffer) < HEADER.size:
            return None
        magic, version, kind, length, sequence, time = HEADER.unpack_from(self._buffer)
        if magic != MAGIC or version != VERSION:
            raise ProtocolError(f"bad frame header (magic {magic!r}, version {version})")
        if length > _MAX_PAYLOAD:
            raise ProtocolError(f"frame payload of {length} bytes is too large")
        end = HEADER.size + length
        if len(self._buffer) < end:
            return None
        payload = bytes(self._buffer[HEADER.size:end])
        del self._buffer[:end]
        return Message(kind, sequence, time, payload)
