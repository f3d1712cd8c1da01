"""Meshcat views of a run: live in a browser, or recorded as one standalone HTML file.

Both draw the robot and the environment bodies (pinocchio's Meshcat visualiser), the
targets of enabled Cartesian tasks, and the active state's name; both are run
observers configured from the world's ``type: meshcat`` processor::

    options = viewer_options(world)
    runner.add_observer(LiveViewer(world, options=options))        # web_url to open
    runner.add_observer(ReplayRecorder(world, "replay.html", options))
"""

from .connection import MeshcatConnection, MeshcatServer
from .errors import ViewerConnectionError, ViewerError
from .live import LiveViewer
from .options import ViewerOptions, viewer_options
from .recorder import ReplayRecorder
from .replay_file import read_replay, replay_html, write_replay
from .scene import Frame, Scene

__all__ = ["LiveViewer", "ReplayRecorder", "ViewerOptions", "viewer_options", "Scene",
           "Frame", "MeshcatServer", "MeshcatConnection", "read_replay", "replay_html",
           "write_replay", "ViewerError", "ViewerConnectionError"]
