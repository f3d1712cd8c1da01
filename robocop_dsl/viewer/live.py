"""The live viewer: a Meshcat server on 127.0.0.1 fed by a publisher thread."""

from __future__ import annotations

import os
import sys
import threading
import time
from typing import Callable

from ..runtime.records import Observer
from .collisions import CollisionLines
from .commands import pack_transform
from .connection import DEFAULT_TIMEOUT, MeshcatConnection, MeshcatServer
from .errors import ViewerConnectionError
from .options import ViewerOptions
from .scene import MovedBodies, Scene

PUBLISHER_NICENESS = 10     # added to the publisher thread's niceness (Linux)


class LiveViewer(Observer):
    """Shows a run in Meshcat as it happens.

    The control thread only stores a reference to each cycle's record (records are
    copies, safe to keep); a publisher thread of its own draws the latest record once
    per viewer period and sends only what changed, at a lower scheduling priority than
    the control thread. A failure of the server (dead, or slower than ``timeout``)
    stops the publisher and is reported once, in :attr:`problems` and through
    ``on_problem``; the control thread never waits for the viewer.

    Attributes:
        web_url: The page that shows the scene.
        zmq_url: The server's ZeroMQ address.
        server: The server started by this viewer, or ``None`` when connected to an
            existing one.
        problems: Messages about failures (at most one).
        published: Number of frames sent so far.
    """

    def __init__(self, world, zmq_url: str | None = None,
                 options: ViewerOptions | None = None, timeout: float = DEFAULT_TIMEOUT,
                 on_problem: Callable[[str], None] | None = None):
        """Start (or connect to) a server, send the scene and start publishing.

        Returns once the publisher thread has sent the scene (or failed to), so that a
        run started next does not share the processor with that burst.

        Args:
            world: The :class:`~robocop_dsl.world.World` being run.
            zmq_url: An existing server's ZeroMQ address; default: start a server on
                127.0.0.1.
            options: The viewer processor's options (the publishing period).
            timeout: Longest wait for one answer of the server [s].
            on_problem: Called once, from the publisher thread, with the message of a
                failure.

        Raises:
            ViewerConnectionError: the server could not be started or reached.
        """
        self.period = (options or ViewerOptions()).period
        self.problems: list = []
        self.published = 0
        self._on_problem = on_problem
        self._scene = Scene(world)
        self._moved = MovedBodies()
        self.server = MeshcatServer() if zmq_url is None else None
        self.zmq_url = zmq_url if self.server is None else self.server.zmq_url
        try:
            self._connection = MeshcatConnection(self.zmq_url, timeout)
        except ViewerConnectionError:
            self._close_server()
            raise
        self.web_url = self._connection.web_url
        self._latest = None
        self._drawn = None
        self._lines: CollisionLines | None = None
        self._lines_loaded = False
        self._closing = False
        self._stopped = False
        self._wake = threading.Event()
        self._progress = threading.Condition()
        self._loaded = threading.Event()
        self._thread = threading.Thread(target=self._publish, name="meshcat-viewer",
                                        daemon=True)
        self._thread.start()
        self._loaded.wait()

    def on_start(self, runner) -> None:
        self._lines = CollisionLines.of_runner(runner)

    def on_cycle(self, record) -> None:
        self._latest = (record, self._moved.update(record))

    def on_stop(self, result) -> None:
        self._wake.set()

    def sync(self, timeout: float) -> bool:
        """Wait up to ``timeout`` [s] for the latest record to be on screen.

        Returns:
            ``True`` when it is, ``False`` on timeout or when the viewer stopped.
        """
        with self._progress:
            self._wake.set()
            self._progress.wait_for(
                lambda: self._stopped or self._drawn is self._latest, timeout)
            return not self._stopped and self._drawn is self._latest

    def close(self) -> None:
        """Publish the latest record, stop the thread, the connection and our server."""
        self._closing = True
        self._wake.set()
        self._thread.join(2 * self._connection.timeout + self.period)
        self._connection.close()
        self._close_server()

    def __enter__(self) -> "LiveViewer":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _close_server(self) -> None:
        if self.server is not None:
            self.server.close()

    def _publish(self) -> None:
        import meshcat

        _lower_thread_priority()
        visualizer = meshcat.Visualizer(window=self._connection)
        try:
            self._scene.load(visualizer)
            self._loaded.set()
            sent: dict = {}
            shown: dict = {}
            deadline = time.monotonic()
            while True:
                closing = self._closing
                latest = self._latest
                if latest is not None and latest is not self._drawn:
                    self._draw(visualizer, latest, sent, shown)
                if closing:
                    break
                deadline = max(deadline + self.period, time.monotonic())
                self._wake.wait(deadline - time.monotonic())
                self._wake.clear()
        except ViewerConnectionError as error:
            self._report(f"viewer stopped: {error}; the run goes on without it")
        except Exception as error:  # the control loop must never see a viewer failure
            self._report(f"viewer stopped: {type(error).__name__}: {error}; "
                         "the run goes on without it")
        finally:
            self._loaded.set()
            with self._progress:
                self._stopped = True
                self._progress.notify_all()

    def _draw(self, visualizer, latest: tuple, sent: dict, shown: dict) -> None:
        record, moved = latest
        self._scene.load_new(visualizer, record)
        frame = self._scene.frame(record, moved)
        poses, visibilities = frame.poses, frame.visible
        if self._lines is not None:
            if not self._lines_loaded:
                self._lines.load(visualizer)
                self._lines_loaded = True
            lines = self._lines.lines(record.q)
            poses, visibilities = {**poses, **lines.transforms()}, {**visibilities,
                                                                     **lines.visible}
        for path, pose in poses.items():
            full_path = visualizer[path].path.lower()
            data = pack_transform(full_path, pose)
            if sent.get(path) != data:
                self._connection.send_packed("set_transform", full_path, data)
                sent[path] = data
        for path, visible in visibilities.items():
            if shown.get(path) != visible:
                visualizer[path].set_property("visible", visible)
                shown[path] = visible
        with self._progress:
            self._drawn = latest
            self.published += 1
            self._progress.notify_all()

    def _report(self, message: str) -> None:
        self.problems.append(message)
        if self._on_problem is not None:
            self._on_problem(message)


def _lower_thread_priority() -> None:
    """Let the control thread win the processor over the calling thread (Linux gives
    each thread its own niceness; elsewhere nothing changes)."""
    if sys.platform.startswith("linux"):
        thread = threading.get_native_id()
        try:
            niceness = os.getpriority(os.PRIO_PROCESS, thread)
            os.setpriority(os.PRIO_PROCESS, thread, niceness + PUBLISHER_NICENESS)
        except OSError:
            pass
