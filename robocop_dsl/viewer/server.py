"""A Meshcat server that listens on the loopback interface only.

meshcat's own server binds its web port on every interface; this one serves the same
page and bridges the same ZeroMQ commands, bound to 127.0.0.1. Run it with
``python -m robocop_dsl.viewer.server [--zmq-url URL] [--allow-remote]``; it prints
``zmq_url=...`` and ``web_url=...`` lines, then serves until interrupted, at a lower
priority than the process that runs the control loop.

A ``--zmq-url`` on another address than loopback (``tcp://0.0.0.0:6010``,
``tcp://*:6010``, a host name) is refused (exit 2) unless ``--allow-remote`` is given;
then the web page is served on that address too: anyone who reaches it may watch and
drive the viewer.
"""

from __future__ import annotations

import argparse
import os
import sys

import tornado.web
from meshcat.servers.zmqserver import (VIEWER_HTML, VIEWER_ROOT, StaticFileHandlerNoCache,
                                       WebSocketHandler, ZMQWebSocketBridge)

from .connection import is_loopback, zmq_host

LOOPBACK = "127.0.0.1"
NICENESS = 10


class _Application(tornado.web.Application):
    """Tornado's application, its web server bound to one address."""

    def __init__(self, handlers, address: str):
        super().__init__(handlers)
        self.address = address

    def listen(self, port, address=None, **kwargs):
        return super().listen(port, address=self.address, **kwargs)


class LoopbackBridge(ZMQWebSocketBridge):
    """meshcat's ZeroMQ-to-websocket bridge, with its web server on ``host``
    (127.0.0.1 unless a remote address was allowed)."""

    def make_app(self):
        return _Application([
            (r"/static/(.*)", StaticFileHandlerNoCache,
             {"path": VIEWER_ROOT, "default_filename": VIEWER_HTML}),
            (r"/", WebSocketHandler, {"bridge": self}),
        ], "" if self.host == "*" else self.host)


def main(argv: list | None = None) -> int:
    """Serve until interrupted; returns the exit code (2: a refused address)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--zmq-url", default=None,
                        help="ZeroMQ address to bind (default: the first free "
                             f"tcp://{LOOPBACK} port from 6000)")
    parser.add_argument("--allow-remote", action="store_true",
                        help="allow a --zmq-url on another address than loopback, and "
                             "serve the web page there too")
    args = parser.parse_args(argv)
    host = LOOPBACK if args.zmq_url is None else zmq_host(args.zmq_url)
    if not is_loopback(host) and not args.allow_remote:
        parser.error(f"--zmq-url {args.zmq_url} listens beyond this machine; use a "
                     f"tcp://{LOOPBACK} address, or add --allow-remote")
    if hasattr(os, "nice"):
        os.nice(NICENESS)
    bridge = LoopbackBridge(zmq_url=args.zmq_url,
                            host=LOOPBACK if is_loopback(host) else host)
    print(f"zmq_url={bridge.zmq_url}", flush=True)
    print(f"web_url={bridge.web_url}", flush=True)
    try:
        bridge.run()
    except KeyboardInterrupt:
        pass
    return 0


if __name__ == "__main__":
    sys.exit(main())
