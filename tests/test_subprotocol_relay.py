"""The relay in front of foxglove-sdk's server: the opening request of a client that
names the protocol ``foxglove.websocket.v1`` alone is renamed, any other passes as it
is (lines may end with LF alone); clients that send no complete request in time, or
one too long, are let go, and connections above the cap are closed as they come;
``[::]`` lets IPv4 clients in; closing the relay ends the connections it carries."""

import contextlib
import socket
import time

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
    """What the peer sends until its head ends, or until it closes (or resets)."""
    data = b""
    while b"\r\n\r\n" not in data:
        try:
            chunk = sock.recv(4096)
        except ConnectionResetError:
            break
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
        assert answer(sock) == b""


def test_a_silent_client_is_let_go(server, monkeypatch):
    monkeypatch.setattr(subprotocol_relay, "HANDSHAKE_TIMEOUT", 0.2)
    with connected(server) as sock:
        sock.sendall(REQUEST)                    # never the blank line
        assert answer(sock) == b""


def test_a_request_trickling_in_is_let_go_after_the_time_for_the_whole(server, monkeypatch):
    """The time is for the whole request: a line every 0.1 s does not extend it."""
    monkeypatch.setattr(subprotocol_relay, "HANDSHAKE_TIMEOUT", 0.5)
    with connected(server) as sock:
        sock.sendall(REQUEST)
        sock.settimeout(0.1)
        for _ in range(200):                     # 20 s of lines, 40 times the time
            try:
                sock.sendall(b"X-Slow: 1\r\n")
                if sock.recv(1) == b"":
                    return
            except TimeoutError:
                continue
            except OSError:                      # reset
                return
        pytest.fail("a request sent line by line was never let go")


def test_lines_ending_with_lf_alone(server):
    request = REQUEST.replace(b"\r\n", b"\n")
    with connected(server) as sock:
        sock.sendall(request + b"Sec-WebSocket-Protocol: foxglove.websocket.v1\n\n")
        head = answer(sock)
    assert head.startswith(b"HTTP/1.1 101")
    assert offered(head.partition(b"\r\n\r\n")[0]) == [b"foxglove.websocket.v1"]


def opened(server, subprotocol: bytes = b"foxglove.sdk.v1") -> tuple:
    """A connection through the relay and the head of the answer to its request."""
    sock = connected(server)
    sock.sendall(REQUEST + b"Sec-WebSocket-Protocol: " + subprotocol + b"\r\n\r\n")
    return sock, answer(sock)


def test_a_client_above_the_cap_is_told_so(server, monkeypatch):
    monkeypatch.setattr(subprotocol_relay, "MAX_CONNECTIONS", 2)
    clients = [opened(server)[0] for _ in range(2)]
    try:
        extra, head = opened(server)
        while chunk := extra.recv(4096):          # the body, until the relay closes
            head += chunk
        extra.close()
        assert head.startswith(b"HTTP/1.1 503")
        assert head.endswith(b"\r\n\r\n2 Foxglove clients are connected already\n")
        clients.pop().close()
        for _ in range(600):                     # once the relay saw the place free
            sock, head = opened(server)
            sock.close()
            if head.startswith(b"HTTP/1.1 101"):
                return
            time.sleep(0.05)
        pytest.fail("the place a closed connection left was never taken again")
    finally:
        for sock in clients:
            sock.close()


def test_silent_connections_do_not_lock_a_client_out(server, monkeypatch):
    """Above the connections still sending their request, the oldest is let go."""
    monkeypatch.setattr(subprotocol_relay, "MAX_WAITING", 3)
    silent = [connected(server) for _ in range(5)]
    try:
        sock, head = opened(server, b"foxglove.websocket.v1")
        sock.close()
        assert head.startswith(b"HTTP/1.1 101")
        assert answer(silent[0]) == b""          # the oldest, let go
    finally:
        for sock in silent:
            sock.close()


@pytest.mark.skipif(not socket.has_dualstack_ipv6(), reason="no dual-stack IPv6 here")
def test_the_ipv6_any_address_lets_ipv4_clients_in():
    server = FoxgloveServer("::", 0, [])
    port = int(server.url.rsplit(":", 1)[1])
    try:
        for host in ("::1", "127.0.0.1"):
            with socket.create_connection((host, port), timeout=30) as sock:
                sock.sendall(REQUEST + b"Sec-WebSocket-Protocol: foxglove.sdk.v1\r\n\r\n")
                assert answer(sock).startswith(b"HTTP/1.1 101")
    finally:
        server.close()


def test_closing_ends_the_connections():
    server = FoxgloveServer("127.0.0.1", 0, [])
    sock = connected(server)
    sock.sendall(REQUEST + b"Sec-WebSocket-Protocol: foxglove.websocket.v1\r\n\r\n")
    assert answer(sock).startswith(b"HTTP/1.1 101")
    server.close()
    while sock.recv(4096):                       # the server's greeting, then the end
        pass
    sock.close()


def test_empty_lines_before_the_request_neither_end_it_nor_extend_its_time(server,
                                                                           monkeypatch):
    """HTTP lets a client send empty lines before its request: they are skipped, the
    request is still renamed, and its time counts from the connection."""
    with connected(server) as sock:
        sock.sendall(b"\r\n\r\n" + REQUEST +
                     b"Sec-WebSocket-Protocol: foxglove.websocket.v1\r\n\r\n")
        head = answer(sock)
    assert offered(head.partition(b"\r\n\r\n")[0]) == [b"foxglove.websocket.v1"]
    monkeypatch.setattr(subprotocol_relay, "HANDSHAKE_TIMEOUT", 0.2)
    with connected(server) as sock:
        sock.sendall(b"\r\n" + REQUEST)          # then nothing
        assert answer(sock) == b""
