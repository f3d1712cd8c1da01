"""The relay in front of foxglove-sdk's server: the opening request of a client that
names the protocol ``foxglove.websocket.v1`` alone is renamed, any other passes as it
is; clients that send no complete request, or one too long, are let go; closing the
relay ends the connections it carries."""

import contextlib
import socket

import pytest

from robocop_dsl.ecosystem import FoxgloveServer, subprotocol_relay
from robocop_dsl.ecosystem.subprotocol_relay import MAX_HEAD, offered, renamed

REQUEST = (b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\n"
           b"Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
           b"Sec-WebSocket-Version: 13\r\n")


def test_the_names_offered_and_renamed():
    head = (b"GET / HTTP/1.1\r\nsec-websocket-protocol: a.v1, foxglove.websocket.v1\r\n"
            b"Sec-WebSocket-Protocol: b.v1\r\nHost: x")
    assert offered(head) == [b"a.v1", b"foxglove.websocket.v1", b"b.v1"]
    again = renamed(head, b"foxglove.sdk.v1")
    assert offered(again) == [b"foxglove.sdk.v1"]
    assert again.split(b"\r\n")[0] == b"GET / HTTP/1.1" and b"Host: x" in again


@pytest.fixture
def server():
    server = FoxgloveServer("127.0.0.1", 0, [])
    yield server
    server.close()


def connected(server) -> socket.socket:
    return socket.create_connection(("127.0.0.1", int(server.url.rsplit(":", 1)[1])),
                                    timeout=30)


def answer(sock: socket.socket) -> bytes:
    """What the peer sends until its head ends, or until it closes."""
    data = b""
    while b"\r\n\r\n" not in data:
        chunk = sock.recv(4096)
        if not chunk:
            break
        data += chunk
    return data


@pytest.mark.parametrize("protocols, expected", [
    (b"foxglove.websocket.v1", b"foxglove.websocket.v1"),
    (b"foxglove.sdk.v1", b"foxglove.sdk.v1"),
    (b"foxglove.websocket.v1, foxglove.sdk.v1", b"foxglove.sdk.v1"),
])
def test_the_client_gets_the_name_it_offered(server, protocols, expected):
    with connected(server) as sock:
        sock.sendall(REQUEST + b"Sec-WebSocket-Protocol: " + protocols + b"\r\n\r\n")
        head = answer(sock)
    assert head.startswith(b"HTTP/1.1 101")
    assert offered(head.partition(b"\r\n\r\n")[0]) == [expected]


def test_a_request_too_long_is_let_go(server):
    with connected(server) as sock:
        with contextlib.suppress(OSError):      # the relay may end it while it is sent
            sock.sendall(REQUEST + b"X-Padding: " + b"x" * (2 * MAX_HEAD) + b"\r\n")
        try:
            got = answer(sock)
        except ConnectionResetError:
            got = b""
    assert got == b""


def test_a_silent_client_is_let_go(server, monkeypatch):
    monkeypatch.setattr(subprotocol_relay, "HANDSHAKE_TIMEOUT", 0.2)
    with connected(server) as sock:
        sock.sendall(REQUEST)                    # never the blank line
        assert answer(sock) == b""


def test_closing_ends_the_connections():
    server = FoxgloveServer("127.0.0.1", 0, [])
    sock = connected(server)
    sock.sendall(REQUEST + b"Sec-WebSocket-Protocol: foxglove.websocket.v1\r\n\r\n")
    assert answer(sock).startswith(b"HTTP/1.1 101")
    server.close()
    while sock.recv(4096):                       # the server's greeting, then the end
        pass
    sock.close()
