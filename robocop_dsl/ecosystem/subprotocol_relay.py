"""The address a Foxglove client connects to, in front of foxglove-sdk's server, so that
clients that name the protocol by its former name get in too.

``foxglove.websocket.v1`` (Lichtblick, Foxglove before 2025, roslibjs-foxglove) and
``foxglove.sdk.v1`` are one protocol under two names, and the SDK's handshake accepts
the second only. The relay passes each connection's bytes to the server unchanged,
but for the opening request of a client that offers the former name alone: the
request goes on naming the current one, and the server's answer names the former one
back. Two threads per connection copy the bytes (the socket calls release the GIL).
"""

from __future__ import annotations

import contextlib
import socket
import threading

CURRENT = b"foxglove.sdk.v1"
FORMER = b"foxglove.websocket.v1"
_HEADER = b"sec-websocket-protocol:"
_END = b"\r\n\r\n"
MAX_HEAD = 1 << 16
"""Bytes of an opening request or its answer at most."""
_CHUNK = 1 << 16
HANDSHAKE_TIMEOUT = 10.0
"""Seconds a client has to send its opening request before it is let go."""


def offered(head: bytes) -> list[bytes]:
    """The subprotocols an HTTP head (request or answer) names, in order."""
    return [name.strip() for line in head.split(b"\r\n")[1:]
            if line.lower().startswith(_HEADER)
            for name in line[len(_HEADER):].split(b",")]


def renamed(head: bytes, names: bytes) -> bytes:
    """``head`` whose subprotocol headers are one naming ``names``."""
    lines = [line for line in head.split(b"\r\n") if not line.lower().startswith(_HEADER)]
    return b"\r\n".join([lines[0], b"Sec-WebSocket-Protocol: " + names, *lines[1:]])


class SubprotocolRelay:
    """Listens on ``host:port`` and relays every connection to the server at
    ``target`` (see the module).

    Attributes:
        port: The port it listens on (the one chosen when asked for 0).

    Raises:
        OSError: it cannot listen there (a port taken, an unknown host).
    """

    def __init__(self, host: str, port: int, target: tuple[str, int]):
        family, _, _, _, address = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)[0]
        self._listener = socket.create_server(address[:2], family=family)
        self.port = self._listener.getsockname()[1]
        self._target = target
        self._sockets: set[socket.socket] = set()
        self._lock = threading.Lock()
        self._closed = False
        threading.Thread(target=self._accept, name="foxglove relay", daemon=True).start()

    def close(self) -> None:
        """Stop listening and end every connection."""
        with self._lock:
            self._closed = True
            sockets, self._sockets = [self._listener, *self._sockets], set()
        for sock in sockets:
            with contextlib.suppress(OSError):
                sock.shutdown(socket.SHUT_RDWR)
            sock.close()

    def _accept(self) -> None:
        while True:
            try:
                client, _ = self._listener.accept()
            except OSError:                 # closed
                return
            threading.Thread(target=self._serve, args=(client,), daemon=True,
                             name="foxglove relay client").start()

    def _serve(self, client: socket.socket) -> None:
        """Relay one connection, its opening request renamed when it must be."""
        if not self._track(client):
            return
        try:
            client.settimeout(HANDSHAKE_TIMEOUT)
            request, rest = _head(client)
            client.settimeout(None)
            server = socket.create_connection(self._target)
        except OSError:
            self._end(client)
            return
        if not self._track(server):
            self._end(client)
            return
        try:
            for sock in (client, server):
                sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            names = offered(request)
            former = FORMER in names and CURRENT not in names
            server.sendall((renamed(request, CURRENT) if former else request) + _END + rest)
            if former:
                answer, rest = _head(server)
                if CURRENT in offered(answer):
                    answer = renamed(answer, FORMER)
                client.sendall(answer + _END + rest)
            threading.Thread(target=self._pump, args=(server, client), daemon=True,
                             name="foxglove relay answer").start()
            self._pump(client, server)
        except OSError:
            self._end(client, server)

    def _track(self, sock: socket.socket) -> bool:
        """Keep ``sock`` to end it on :meth:`close`; close it at once (and say no) when
        the relay is closed already."""
        with self._lock:
            if not self._closed:
                self._sockets.add(sock)
                return True
        sock.close()
        return False

    def _pump(self, source: socket.socket, sink: socket.socket) -> None:
        """Copy ``source``'s bytes to ``sink`` until either ends, then end both."""
        try:
            while True:
                data = source.recv(_CHUNK)
                if not data:
                    break
                sink.sendall(data)
        except OSError:
            pass
        self._end(source, sink)

    def _end(self, *sockets: socket.socket) -> None:
        with self._lock:
            self._sockets -= set(sockets)
        for sock in sockets:
            with contextlib.suppress(OSError):
                sock.shutdown(socket.SHUT_RDWR)
            sock.close()


def _head(sock: socket.socket) -> tuple[bytes, bytes]:
    """The HTTP head read from ``sock`` (without its blank line) and the bytes read
    after it.

    Raises:
        OSError: the peer closed first, or the head is longer than :data:`MAX_HEAD`.
    """
    data = b""
    while _END not in data:
        chunk = sock.recv(_CHUNK)
        if not chunk or len(data) > MAX_HEAD:
            raise ConnectionError("no complete HTTP head")
        data += chunk
    head, _, rest = data.partition(_END)
    return head, rest
