"""The address a Foxglove client connects to, in front of foxglove-sdk's server, so that
clients that name the protocol by its former name get in too.

``foxglove.websocket.v1`` (Lichtblick, Foxglove before 2025, roslibjs-foxglove) and
``foxglove.sdk.v1`` are one protocol under two names, and the SDK's handshake accepts
the second only. The relay passes each connection's bytes to the server unchanged,
but for the opening request of a client that offers the former name alone: the
request goes on naming the current one, and the server's answer names the former one
back. One thread serves every connection (an asyncio loop, waiting outside the GIL),
at most :data:`MAX_CONNECTIONS` at once and :data:`MAX_WAITING` still sending their
request: a burst of connections costs the run's process little.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
import socket
import threading

CURRENT = b"foxglove.sdk.v1"
FORMER = b"foxglove.websocket.v1"
_HEADER = b"sec-websocket-protocol:"
MAX_HEAD = 1 << 16
"""Bytes of an opening request or its answer at most."""
HANDSHAKE_TIMEOUT = 10.0
"""Seconds a client has to send its whole opening request before it is let go."""
MAX_CONNECTIONS = 64
"""Connections relayed at once at most; a client above them gets an HTTP 503."""
MAX_WAITING = 16
"""Connections whose opening request is still coming at most; a new one lets the
oldest go (a flood of silent connections does not lock out a client whose request
comes at once)."""
CLOSING_TIME = 1.0
"""Seconds the connections have to end on their own when the relay closes (the
server's closing frames reaching the clients) before they are cut."""
_CHUNK = 1 << 16


def offered(head: bytes) -> list[bytes]:
    """The subprotocols an HTTP head (request or answer) names, in order."""
    return [name.strip() for line in head.splitlines()[1:]
            if line.lower().startswith(_HEADER)
            for name in line[len(_HEADER):].split(b",")]


def renamed(head: bytes, names: bytes) -> bytes:
    """``head`` whose subprotocol headers are one naming ``names`` (lines ending as its
    first line does)."""
    lines = head.splitlines(keepends=True)
    end = lines[0][len(lines[0].rstrip(b"\r\n")):] or b"\r\n"
    kept = [line for line in lines[1:] if not line.lower().startswith(_HEADER)]
    return b"".join([lines[0], b"Sec-WebSocket-Protocol: " + names + end, *kept])


def listening_socket(host: str, port: int) -> socket.socket:
    """A socket listening on ``host:port`` (the first address ``host`` resolves to, its
    IPv6 scope kept; IPv4 clients too on ``::``, as on ``0.0.0.0``).

    Raises:
        OSError: it cannot listen there (a port taken, an unknown host).
    """
    family, _, _, _, address = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)[0]
    both = (family == socket.AF_INET6 and address[0] == "::"
            and socket.has_dualstack_ipv6())
    return socket.create_server(address, family=family, dualstack_ipv6=both)


class SubprotocolRelay:
    """Listens on ``host:port`` and relays every connection to the server at
    ``target`` (see the module).

    Attributes:
        port: The port it listens on (the one chosen when asked for 0).

    Raises:
        OSError: it cannot listen there (a port taken, an unknown host).
    """

    def __init__(self, host: str, port: int, target: tuple[str, int]):
        listener = listening_socket(host, port)
        self.port = listener.getsockname()[1]
        self._target = target
        self._waiting: dict[asyncio.Task, None] = {}
        """The connections whose opening request is still coming, oldest first."""
        self._relayed: set[asyncio.Task] = set()
        self._loop = asyncio.new_event_loop()
        self._loop.set_exception_handler(lambda loop, context: None)
        self._server = self._loop.run_until_complete(
            asyncio.start_server(self._serve, sock=listener, limit=MAX_HEAD))
        self._thread = threading.Thread(target=self._loop.run_forever,
                                        name="foxglove relay", daemon=True)
        self._thread.start()

    def close(self) -> None:
        """Stop listening, let go the clients still sending their opening request, give
        the others :data:`CLOSING_TIME` to end, then cut them."""
        if self._loop.is_closed():
            return
        closing = asyncio.run_coroutine_threadsafe(self._close(), self._loop)
        with contextlib.suppress(concurrent.futures.TimeoutError):
            closing.result(timeout=CLOSING_TIME + 1.0)
        self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join()
        self._loop.close()

    async def _close(self) -> None:
        self._server.close()
        waiting = list(self._waiting)
        for task in waiting:
            task.cancel()
        late = set()
        if self._relayed:
            _, late = await asyncio.wait(self._relayed, timeout=CLOSING_TIME)
            for task in late:
                task.cancel()
        await asyncio.gather(*waiting, *late, return_exceptions=True)

    async def _serve(self, reader: asyncio.StreamReader,
                     writer: asyncio.StreamWriter) -> None:
        """Relay one connection: its opening request awaited among at most
        :data:`MAX_WAITING` (the oldest let go for a new one), then relayed among at
        most :data:`MAX_CONNECTIONS` (above, an HTTP 503 that says so)."""
        task = asyncio.current_task()
        if len(self._waiting) >= MAX_WAITING:
            oldest = next(iter(self._waiting))
            del self._waiting[oldest]
            oldest.cancel()
        self._waiting[task] = None
        try:
            request = await asyncio.wait_for(_head(reader), HANDSHAKE_TIMEOUT)
            del self._waiting[task]
            if len(self._relayed) >= MAX_CONNECTIONS:
                writer.write(_busy())
                await writer.drain()
                return
            self._relayed.add(task)
            await self._relay(request, reader, writer)
        except (OSError, EOFError, ValueError, asyncio.TimeoutError):
            pass
        finally:
            self._waiting.pop(task, None)
            self._relayed.discard(task)
            _end(writer)

    async def _relay(self, request: bytes, reader: asyncio.StreamReader,
                     writer: asyncio.StreamWriter) -> None:
        """The opening request, renamed when it must be, then the bytes both ways."""
        names = offered(request)
        former = FORMER in names and CURRENT not in names
        server_reader, server_writer = await asyncio.open_connection(*self._target,
                                                                     limit=MAX_HEAD)
        try:
            server_writer.write(renamed(request, CURRENT) if former else request)
            if former:
                answer = await asyncio.wait_for(_head(server_reader), HANDSHAKE_TIMEOUT)
                writer.write(renamed(answer, FORMER) if CURRENT in offered(answer)
                             else answer)
            await asyncio.gather(_pump(reader, server_writer), _pump(server_reader, writer))
        finally:
            _end(server_writer)


def _busy() -> bytes:
    """The answer to a client above :data:`MAX_CONNECTIONS`."""
    text = f"{MAX_CONNECTIONS} Foxglove clients are connected already\n".encode()
    return (b"HTTP/1.1 503 Service Unavailable\r\nContent-Type: text/plain\r\n"
            b"Content-Length: %d\r\nConnection: close\r\n\r\n" % len(text) + text)


async def _head(reader: asyncio.StreamReader) -> bytes:
    """An HTTP head read from ``reader``, its blank line included (lines may end with
    CRLF or LF alone; empty lines before it are read and left out, as HTTP allows).

    Raises:
        EOFError: the peer closed first.
        ValueError: more than :data:`MAX_HEAD` bytes were read.
    """
    head, read = b"", 0
    while True:
        line = await reader.readline()
        if not line.endswith(b"\n"):
            raise EOFError("no complete HTTP head")
        read += len(line)
        if read > MAX_HEAD:
            raise ValueError("HTTP head too long")
        blank = line in (b"\r\n", b"\n")
        if blank and head:
            return head + line
        if not blank:
            head += line


async def _pump(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
    """Pass ``reader``'s bytes to ``writer`` until their end, then end ``writer``'s
    side (the other direction goes on until its own end)."""
    while data := await reader.read(_CHUNK):
        writer.write(data)
        await writer.drain()
    if writer.can_write_eof():
        writer.write_eof()
    else:
        writer.close()


def _end(writer: asyncio.StreamWriter) -> None:
    """Close a connection: at once when bytes still wait to go (a peer that does not
    read, or one that went away)."""
    transport = writer.transport
    if transport.get_write_buffer_size():
        transport.abort()
    else:
        transport.close()
