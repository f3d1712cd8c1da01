"""Talking to a Meshcat server: starting one on 127.0.0.1, and a window that sends
commands over ZeroMQ without ever waiting longer than a timeout."""

from __future__ import annotations

import ipaddress
import os
import selectors
import subprocess
import sys
import time
import weakref
from urllib.parse import urlsplit

import zmq

from .commands import pack
from .errors import ViewerConnectionError

DEFAULT_TIMEOUT = 2.0   # [s] for one answer of the server
START_TIMEOUT = 20.0    # [s] for a new server to report its addresses


def zmq_host(zmq_url: str) -> str | None:
    """The host a ``tcp://HOST:PORT`` address binds (``None`` for a local transport:
    ``ipc://``, ``inproc://``)."""
    parts = urlsplit(zmq_url)
    if parts.scheme in ("ipc", "inproc"):
        return None
    return parts.netloc.rpartition(":")[0].strip("[]") or parts.netloc


def is_loopback(host: str | None) -> bool:
    """Whether binding ``host`` (from :func:`zmq_host`) stays on this machine."""
    if host is None or host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


class MeshcatServer:
    """A Meshcat server process of our own (:mod:`robocop_dsl.viewer.server`).

    Attributes:
        zmq_url: Where commands go, e.g. ``tcp://127.0.0.1:6000``.
        web_url: The page to open, e.g. ``http://127.0.0.1:7000/static/``.
    """

    def __init__(self, zmq_url: str | None = None, timeout: float = START_TIMEOUT,
                 allow_remote: bool = False):
        """Start the server and wait for its addresses.

        Args:
            zmq_url: ZeroMQ address to bind; default: the first free loopback port.
            timeout: How long to wait for the server to come up [s].
            allow_remote: Allow a ``zmq_url`` beyond loopback (the web page is then
                served on that address too).

        Raises:
            ViewerConnectionError: a remote ``zmq_url`` not allowed, or the server
                exited or did not report in time.
        """
        command = [sys.executable, "-m", "robocop_dsl.viewer.server"]
        if zmq_url is not None:
            if not allow_remote and not is_loopback(zmq_host(zmq_url)):
                raise ViewerConnectionError(
                    f"'{zmq_url}' listens beyond this machine: a Meshcat server binds a "
                    "loopback address unless remote access is allowed", zmq_url)
            command += ["--zmq-url", zmq_url]
        if allow_remote:
            command.append("--allow-remote")
        self.process = subprocess.Popen(command, stdout=subprocess.PIPE,
                                        stderr=subprocess.DEVNULL)
        self._finalizer = weakref.finalize(self, _stop_process, self.process)
        try:
            values = _read_addresses(self.process, timeout)
        except ViewerConnectionError:
            self.close()
            raise
        self.zmq_url = values["zmq_url"]
        self.web_url = values["web_url"]

    def close(self) -> None:
        """Stop the server process (idempotent; also done when the interpreter exits)."""
        self._finalizer()


def _stop_process(process) -> None:
    if process.poll() is None:
        process.terminate()
        try:
            process.wait(timeout=5)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
    process.stdout.close()


def _read_addresses(process, timeout: float) -> dict:
    """The ``zmq_url`` and ``web_url`` a starting server prints, read without buffering
    so that the deadline holds."""
    text, values = "", {}
    deadline = time.monotonic() + timeout
    descriptor = process.stdout.fileno()
    with selectors.DefaultSelector() as selector:
        selector.register(descriptor, selectors.EVENT_READ)
        while not {"zmq_url", "web_url"} <= values.keys():
            remaining = deadline - time.monotonic()
            if remaining <= 0 or not selector.select(remaining):
                raise ViewerConnectionError(
                    f"the Meshcat server did not start within {timeout:g} s")
            chunk = os.read(descriptor, 4096)
            if not chunk:
                raise ViewerConnectionError(
                    f"the Meshcat server exited with code {process.wait()} while starting")
            text += chunk.decode("utf-8")
            values = dict(line.strip().split("=", 1) for line in text.splitlines(True)
                          if line.endswith("\n") and "=" in line)
    return values


class MeshcatConnection:
    """A Meshcat window over ZeroMQ: ``meshcat.Visualizer(window=connection)``.

    Unlike meshcat's own window it prints nothing, and every exchange with the server
    gives up after ``timeout``, raising :class:`ViewerConnectionError`; the connection
    is unusable afterwards.
    """

    context = zmq.Context.instance()

    def __init__(self, zmq_url: str, timeout: float = DEFAULT_TIMEOUT):
        """Connect and ask the server for its web address.

        Args:
            zmq_url: The server's ZeroMQ address.
            timeout: Longest wait for one answer [s].

        Raises:
            ViewerConnectionError: the address is not a ZeroMQ one, or the server did
                not answer in time.
        """
        self.zmq_url = zmq_url
        self.timeout = timeout
        self._socket = None
        self._connect()
        try:
            self._socket.send(b"url")
            self.web_url = self._receive().decode("utf-8")
        except ViewerConnectionError:
            self.close()
            raise
        # meshcat's server misses later commands from the socket that asked for the
        # address until the client reconnects (as meshcat's own window does)
        self._connect()

    def _connect(self) -> None:
        if self._socket is not None:
            self._socket.close(linger=0)
        self._socket = self.context.socket(zmq.REQ)
        milliseconds = max(1, int(self.timeout * 1000))
        self._socket.setsockopt(zmq.RCVTIMEO, milliseconds)
        self._socket.setsockopt(zmq.SNDTIMEO, milliseconds)
        self._socket.setsockopt(zmq.LINGER, 0)
        try:
            self._socket.connect(self.zmq_url)
        except zmq.ZMQError as error:
            self.close()
            raise ViewerConnectionError(
                f"cannot connect to a Meshcat server at '{self.zmq_url}': {error}",
                self.zmq_url) from error

    def _receive(self) -> bytes:
        try:
            return self._socket.recv()
        except zmq.Again as error:
            raise ViewerConnectionError(
                f"the Meshcat server at {self.zmq_url} did not answer within "
                f"{self.timeout:g} s", self.zmq_url) from error

    def send(self, command) -> None:
        """Send one meshcat command object and wait for the server's acknowledgement.

        Raises:
            ViewerConnectionError: no acknowledgement within the timeout.
        """
        data = command.lower()
        self.send_packed(data["type"], data["path"], pack(data))

    def send_packed(self, kind: str, path: str, data: bytes) -> None:
        """Send one command already packed (see :func:`commands.pack_transform`).

        Args:
            kind: The command's type, e.g. ``set_transform``.
            path: The node's full Meshcat path.
            data: The packed command.

        Raises:
            ViewerConnectionError: no acknowledgement within the timeout.
        """
        try:
            self._socket.send_multipart([kind.encode("utf-8"), path.encode("utf-8"), data])
        except zmq.ZMQError as error:
            raise ViewerConnectionError(
                f"cannot send to the Meshcat server at {self.zmq_url}: {error}",
                self.zmq_url) from error
        self._receive()

    def close(self) -> None:
        """Close the socket (idempotent)."""
        if self._socket is not None:
            self._socket.close(linger=0)
            self._socket = None
