"""A Meshcat server that listens on the loopback interface only.

meshcat's own server binds its web port on every interface; this one serves the same
page and bridges the same ZeroMQ commands, bound to 127.0.0.1. Run it with
``python -m robocop_dsl.viewer.server [--zmq-url URL]``; it prints ``zmq_url=...`` and
``web_url=...`` lines, then serves until interrupted, at a lower priority than the
process that runs the control loop.
"""

from __future__ import annotations

import argparse
import os
import sys

import tornado.web
from meshcat.servers.zmqserver import (VIEWER_HTML, VIEWER_ROOT, StaticFileHandlerNoCache,
                                       WebSocketHandler, ZMQWebSocketBridge)

LOOPBACK = "127.0.0.1"
NICENESS = 10


class _LoopbackApplication(tornado.web.Application):
    def listen(self, port, address=LOOPBACK, **kwargs):
        return super().listen(port, address=LOOPBACK, **kwargs)


class LoopbackBridge(ZMQWebSocketBridge):
    """meshcat's ZeroMQ-to-websocket bridge, with its web server on 127.0.0.1."""

    def make_app(self):
        return _LoopbackApplication([
            (r"/static/(.*)", StaticFileHandlerNoCache,
             {"path": VIEWER_ROOT, "default_filename": VIEWER_HTML}),
            (r"/", WebSocketHandler, {"bridge": self}),
        ])


def main(argv: list | None = None) -> int:
    """Serve until interrupted; returns the exit code."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--zmq-url", default=None,
                        help="ZeroMQ address to bind (default: the first free "
                             f"tcp://{LOOPBACK} port from 6000)")
    args = parser.parse_args(argv)
    if hasattr(os, "nice"):
        os.nice(NICENESS)
    bridge = LoopbackBridge(zmq_url=args.zmq_url, host=LOOPBACK)
    print(f"zmq_url={bridge.zmq_url}", flush=True)
    print(f"web_url={bridge.web_url}", flush=True)
    try:
        bridge.run()
    except KeyboardInterrupt:
        pass
    return 0


if __name__ == "__main__":
    sys.exit(main())
