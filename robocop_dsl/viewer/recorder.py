"""Recording a run as a standalone HTML replay."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..runtime.records import Observer
from .collisions import CollisionLines
from .commands import CommandLog
from .geometry import WorldGeometry
from .options import ViewerOptions
from .replay_file import write_replay
from .scene import MovedBodies, Scene

TIME_TOLERANCE = 1e-9   # [s] a cycle this close to a frame's time is that frame's
DEFAULT_TITLE = "robocop-mission replay"


class ReplayRecorder(Observer):
    """An observer that writes one HTML file replaying the run when it stops.

    Frame ``i`` of the replay shows the latest cycle at or before ``t0 + i * period``
    (``t0``: the first cycle's time), so the animation has one frame per viewer period
    of run time and plays in real time; when the run stops between two frame times, one
    more frame shows its last cycle. On a cycle the recorder only keeps a reference
    to the record at each frame time; the drawing commands are made when the file is
    written. Make the recorder before the run (see
    :class:`~robocop_dsl.viewer.geometry.WorldGeometry`).

    Attributes:
        path: Where the replay is written.
        title: The page title; default: the mission's name, given by the runner.
        problems: Messages about a replay that could not be written (the run is never
            interrupted by the recorder).
    """

    def __init__(self, world, path: str | Path, options: ViewerOptions | None = None,
                 title: str | None = None):
        self.path = Path(path)
        self.period = (options or ViewerOptions()).period
        self.title = title
        self.problems: list = []
        self._world = world
        self._geometry = WorldGeometry(world)
        self._moved = MovedBodies()
        self._frames: list = []
        self._previous = None
        self._start: float | None = None
        self._lines: CollisionLines | None = None

    def on_start(self, runner) -> None:
        if self.title is None and runner is not None:
            self.title = f"{runner.name}: robocop-mission replay"
        if runner is not None:
            self._lines = CollisionLines.of_runner(runner)

    def on_cycle(self, record) -> None:
        current = (record, self._moved.update(record))
        if self._start is None:
            self._start = record.time
        while self._frame_time(len(self._frames)) < record.time - TIME_TOLERANCE \
                and self._previous is not None:
            self._frames.append(self._previous)
        if abs(self._frame_time(len(self._frames)) - record.time) <= TIME_TOLERANCE:
            self._frames.append(current)
        self._previous = current

    def _frame_time(self, index: int) -> float:
        return self._start + index * self.period

    @property
    def frame_records(self) -> list:
        """The record shown by each frame so far, in order."""
        return [record for record, _ in self._frames]

    def on_stop(self, result) -> None:
        if self._previous is not None and self._frames[-1] is not self._previous:
            self._frames.append(self._previous)
        try:
            self.write()
        except OSError as error:
            self.problems.append(f"could not write the replay {self.path}: {error}")

    def write(self) -> Path:
        """Write the replay of the frames recorded so far; returns its path."""
        return write_replay(self.path, self.commands(), self.title or DEFAULT_TITLE)

    def commands(self) -> list:
        """The replay's lowered Meshcat commands: the scene, then the animation."""
        import meshcat

        log = CommandLog()
        visualizer = meshcat.Visualizer(window=log)
        scene = Scene(self._world, self._geometry)
        scene.load(visualizer)
        for record, _ in self._frames:
            scene.load_new(visualizer, record)
        frames = [scene.frame(record, moved) for record, moved in self._frames]
        scales: list = [{} for _ in frames]
        if self._lines is not None:
            self._lines.load(visualizer)
            for frame, scale, (record, _) in zip(frames, scales, self._frames):
                lines = self._lines.lines(record.q)
                frame.poses.update(lines.poses)
                frame.visible.update(lines.visible)
                scale.update(lines.scales)
        if frames:
            _animate(visualizer, frames, self.period, scales)
        return log.commands


def _animate(visualizer, frames: list, period: float, scales: list) -> None:
    """Send the first frame as plain commands, then one animation with a track for
    every pose, stretch (``scales``: path -> scale per frame, for collision lines) or
    visibility that changes during the run."""
    from meshcat.animation import Animation

    poses = _pose_series(frames)
    stretch = _series([{path: np.diag([*scale, 1.0]) for path, scale in s.items()}
                       for s in scales])
    for path, series in poses.items():
        visualizer[path].set_transform(series[0] @ stretch[path][0] if path in stretch
                                       else series[0])
    for path, visible in frames[0].visible.items():
        visualizer[path].set_property("visible", visible)
    animation = Animation(default_framerate=1.0 / period)
    for path, series in poses.items():
        if any(not np.array_equal(series[0], pose) for pose in series[1:]):
            for index, pose in enumerate(series):
                position, quaternion = _position_quaternion(pose)
                node = animation.at_frame(visualizer, index)[path]
                node.set_property("position", "vector3", position)
                node.set_property("quaternion", "quaternion", quaternion)
    for path, series in stretch.items():
        if any(not np.array_equal(series[0], scale) for scale in series[1:]):
            for index, scale in enumerate(series):
                animation.at_frame(visualizer, index)[path].set_property(
                    "scale", "vector3", [float(v) for v in np.diag(scale)[:3]])
    for path in frames[-1].visible:
        series = [frame.visible.get(path, False) for frame in frames]
        if any(value != series[0] for value in series[1:]):
            for index, value in enumerate(series):
                animation.at_frame(visualizer, index)[path].set_property(
                    "visible", "boolean", value)
    if animation.clips:
        visualizer.set_animation(animation, play=True, repetitions=1)


def _position_quaternion(pose: np.ndarray) -> tuple:
    """Position [m] and three.js quaternion (x, y, z, w) of a rigid pose."""
    from meshcat.transformations import quaternion_from_matrix

    w, x, y, z = quaternion_from_matrix(pose)
    return [float(v) for v in pose[:3, 3]], [float(x), float(y), float(z), float(w)]


def _pose_series(frames: list) -> dict:
    """Path -> one pose per frame; a marker keeps its last pose while hidden (and its
    first one before it shows up)."""
    return _series([frame.poses for frame in frames])


def _series(values: list) -> dict:
    """Path -> one value per frame from one mapping per frame; a path keeps its last
    value where a mapping lacks it (and its first one before it shows up)."""
    paths = list(dict.fromkeys(path for frame in values for path in frame))
    series = {}
    for path in paths:
        known = [frame.get(path) for frame in values]
        first = next(pose for pose in known if pose is not None)
        filled, last = [], first
        for pose in known:
            last = pose if pose is not None else last
            filled.append(last)
        series[path] = filled
    return series
