"""The run live over the Foxglove WebSocket protocol (foxglove-sdk's server): the same
topics as ``run.mcap``, on 127.0.0.1:8765 unless told otherwise; serving any address
but the loopback's needs the caller's explicit consent (``--allow-remote``), as the
data goes to whoever connects.

A client that subscribes to a latched topic (the URDF, the fixed bodies, the state,
the targets) gets its last message at once; the first to subscribe to the events
(``/mission/events``, ``/rosout``) gets the run's last ones (the server sends a message
to every subscriber of its channel: a client that subscribes beside another gets the
events from then on, and the other none twice)."""

from __future__ import annotations

import ipaddress
import socket
import threading
from collections import deque

from ..diagnostics import RobocopError
from .msgdefs import message_definition
from .subprotocol_relay import SubprotocolRelay

DEFAULT_ADDRESS = "127.0.0.1:8765"


class FoxgloveError(RobocopError):
    """A Foxglove server that cannot be started: a port taken, an unknown host."""


class FoxgloveAddressError(FoxgloveError):
    """An address that is not ``HOST:PORT``, or not the loopback's without consent."""


def parse_address(text: str, allow_remote: bool = False) -> tuple:
    """``(host, port)`` of ``HOST:PORT`` (``[::1]:PORT`` for IPv6; port 0: any free).

    Raises:
        FoxgloveAddressError: not ``HOST:PORT``, a port out of 0..65535, or a host that
            is not the loopback without ``allow_remote``.
    """
    host, colon, port = text.rpartition(":")
    bracketed = host.startswith("[") and host.endswith("]")
    host = host[1:-1] if bracketed else host
    if ":" in host and not bracketed:
        raise FoxgloveAddressError(f"--foxglove '{text}': an IPv6 address goes in brackets, "
                                   "the port after them (e.g. [::1]:8765)")
    if not colon or not host or not port.isdigit() or int(port) > 65535:
        raise FoxgloveAddressError(f"--foxglove '{text}': expected HOST:PORT, a port from 0 "
                                   f"to 65535 (e.g. {DEFAULT_ADDRESS})")
    if not allow_remote and not _loopback(host):
        raise FoxgloveAddressError(f"--foxglove '{text}': {host} is not the loopback address, "
                                   "so anyone who reaches this machine could watch the run; "
                                   "add --allow-remote to serve it there anyway")
    return host, int(port)


def _in_url(host: str) -> str:
    """``host`` as a URL writes it: an IPv6 address in brackets."""
    return f"[{host}]" if ":" in host else host


def _named(host: str) -> str:
    """``host`` as a client names it in a URL: this machine's name for an address that
    stands for all of its own (``0.0.0.0``, ``::``)."""
    try:
        if ipaddress.ip_address(host).is_unspecified:
            return _in_url(socket.gethostname())
    except ValueError:
        pass
    return _in_url(host)


def _loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


class FoxgloveServer:
    """A Foxglove WebSocket server with one channel per topic, CDR messages with their
    ROS 2 definitions (a sink of :class:`~.stream.TopicStream`). foxglove-sdk's server
    listens on the loopback; clients connect to a
    :class:`~.subprotocol_relay.SubprotocolRelay` in front of it, which lets in those
    that name the protocol ``foxglove.websocket.v1`` as well as ``foxglove.sdk.v1``.

    Args:
        host: The address to serve on.
        port: Its port (0: any free one).
        topics: The :class:`~.topics.Topic` s to advertise.
        name: The server's name, shown by Foxglove.

    Attributes:
        url: ``ws://HOST:PORT`` to open in Foxglove (this machine's name for a server on
            all of its addresses).

    Raises:
        FoxgloveError: the server cannot listen there (a port taken, an unknown host).
    """

    def __init__(self, host: str, port: int, topics: list, name: str = "robocop-mission"):
        import foxglove

        self._context = foxglove.Context()
        try:
            self._server = foxglove.start_server(name=name, host="127.0.0.1", port=0,
                                                 context=self._context,
                                                 server_listener=self)
        except RuntimeError as error:
            reason = str(error).removeprefix("FoxgloveError: ")
            raise FoxgloveError(f"cannot serve Foxglove: {reason}") from None
        shown = _in_url(host)
        try:
            self._relay = SubprotocolRelay(host, port, ("127.0.0.1", self._server.port))
        except OSError as error:
            self._server.stop()
            reason = error.strerror or str(error)
            raise FoxgloveError(f"cannot serve Foxglove on {shown}:{port}: {reason}") from None
        self.url = f"ws://{_named(host)}:{self._relay.port}"
        self._latched = {topic.name: None for topic in topics if topic.latched}
        self._history = {topic.name: deque(maxlen=topic.history) for topic in topics
                         if topic.history}
        self._subscribers: dict = {topic.name: set() for topic in topics}
        self._kept = threading.Lock()
        """Held while a message is kept (before it is sent: a client that subscribes
        meanwhile gets it, once or, rarely, twice, never not at all) and while a
        subscriber is counted and what was kept is read; never while sending."""
        self._channels = {
            topic.name: foxglove.Channel(
                topic.name, message_encoding="cdr", context=self._context,
                schema=foxglove.Schema(name=topic.type, encoding="ros2msg",
                                       data=message_definition(topic.type).encode()))
            for topic in topics}

    def write(self, messages: list) -> None:
        """Send ``(topic, time [ns], bytes)`` messages to the subscribed clients."""
        for topic, time, data in messages:
            with self._kept:
                if topic in self._latched:
                    self._latched[topic] = (int(time), data)
                if topic in self._history:
                    self._history[topic].append((int(time), data))
            self._channels[topic].log(data, log_time=int(time))

    def checkpoint(self) -> None:
        """Nothing to do: messages go out as they are written."""

    def close(self) -> None:
        """Stop the server (its clients get a closing frame through the relay), then
        the relay."""
        self._server.stop()
        self._relay.close()

    def on_subscribe(self, client, channel) -> None:
        """Called by the server: send a latched topic's last message, and to the first
        subscriber of a topic with a history its last messages."""
        topic = channel.topic
        with self._kept:
            first = not self._subscribers[topic]
            self._subscribers[topic].add(client.id)
            last = self._latched.get(topic)
            kept = ([] if last is None else [last]) + (
                list(self._history.get(topic, ())) if first else [])
        for time, data in kept:
            self._channels[topic].log(data, log_time=time)

    def on_unsubscribe(self, client, channel) -> None:
        """Called by the server when a client unsubscribes or leaves."""
        with self._kept:
            self._subscribers[channel.topic].discard(client.id)
