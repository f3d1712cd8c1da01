"""The loopback protocol's frames, over a real socket pair."""

import socket

import numpy as np
import pytest

from robocop_dsl.drivers import protocol


@pytest.fixture
def pair():
    """Two protocol endpoints connected over TCP on 127.0.0.1."""
    with socket.create_server((protocol.HOST, 0)) as server:
        left = socket.create_connection(server.getsockname())
        right, _ = server.accept()
    left.settimeout(2.0)
    right.settimeout(2.0)
    a, b = protocol.Connection(left), protocol.Connection(right)
    yield a, b
    a.close()
    b.close()


def test_header_layout():
    """The header is 24 bytes, little-endian, magic first (docs/driver_protocol.md)."""
    frame = protocol.encode(protocol.COMMAND, 7, 1.5, b"\x01\x02")
    assert len(frame) == protocol.HEADER.size + 2 == 26
    assert frame[:4] == b"RC\x01\x03"
    assert frame[4:8] == (2).to_bytes(4, "little")
    assert frame[8:16] == (7).to_bytes(8, "little")
    assert np.frombuffer(frame[16:24], "<f8")[0] == 1.5


def test_state_round_trip(pair):
    """A STATE frame carries position, velocity and the holding flag unchanged."""
    a, b = pair
    a.send(protocol.STATE, 3, 0.25, protocol.state_payload([1.0, 2.0, 3.0], [0.5, -0.5], True))
    message = b.receive()
    assert (message.kind, message.sequence, message.time) == (protocol.STATE, 3, 0.25)
    position, velocity, holding = protocol.decode_state(message, 3, 2)
    np.testing.assert_array_equal(position, [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(velocity, [0.5, -0.5])
    assert holding is True


def test_hello_and_command_round_trip(pair):
    """HELLO names the joints; COMMAND carries the velocities."""
    a, b = pair
    hello = protocol.Hello(3, 2, 0.001, ("wheel", "slider"))
    a.send(protocol.HELLO, 0, 0.0, protocol.hello_payload(hello))
    b.send(protocol.COMMAND, 9, 1.0, protocol.command_payload([0.1, 0.2]))
    assert protocol.decode_hello(b.receive()) == hello
    np.testing.assert_array_equal(protocol.decode_command(a.receive(), 2), [0.1, 0.2])


def test_frames_split_and_merged_on_the_wire(pair):
    """Frames arriving in pieces or glued together are cut correctly."""
    a, b = pair
    frames = [protocol.encode(protocol.COMMAND, k, 0.0, protocol.command_payload([k]))
              for k in range(1, 4)]
    data = b"".join(frames)
    a.sock.sendall(data[:5])
    assert b.poll() == []
    a.sock.sendall(data[5:40])
    assert b.receive().sequence == 1
    a.sock.sendall(data[40:])
    assert [m.sequence for m in [b.receive(), b.receive()]] == [2, 3]


def test_bad_frames_are_refused(pair):
    """A wrong magic, or a payload of the wrong size, is a ProtocolError."""
    a, b = pair
    a.sock.sendall(b"XX" + bytes(22))
    with pytest.raises(protocol.ProtocolError, match="bad frame header"):
        b.receive()
    message = protocol.Message(protocol.COMMAND, 1, 0.0, bytes(8))
    with pytest.raises(protocol.ProtocolError, match="expected 16"):
        protocol.decode_command(message, 2)


def test_closed_peer_is_a_connection_error(pair):
    """The peer closing the connection ends receive() with ConnectionError."""
    a, b = pair
    a.close()
    with pytest.raises(ConnectionError):
        b.receive()
