"""What the viewer draws for a world, and where each part of it is at one cycle."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import camera, labels, targets
from .geometry import WorldGeometry

LABEL_HEIGHT = 0.1      # [m] of the state label above the scene's top


@dataclass
class Frame:
    """The drawable state of one cycle.

    Attributes:
        time: Run time of the cycle [s].
        state: The active state's name.
        poses: Meshcat path -> 4x4 world pose [m] of every body node and of the
            markers of enabled tasks.
        visible: Meshcat path -> visibility of every task marker and state label
            the scene has loaded.
    """

    time: float
    state: str
    poses: dict = field(default_factory=dict)
    visible: dict = field(default_factory=dict)


class MovedBodies:
    """Where the environment bodies moved by the run are.

    A record gives the pose of the bodies attached at that cycle; a detached body stays
    where it was left, so its last reported pose is kept. :meth:`update` makes a new
    mapping when something moved, so a mapping handed to another thread never changes.

    Attributes:
        poses: Body name -> 4x4 world pose [m].
    """

    def __init__(self):
        self.poses: dict = {}

    def update(self, record) -> dict:
        """Take in a record's attached bodies; returns the current mapping."""
        if record.body_poses:
            self.poses = {**self.poses, **record.body_poses}
        return self.poses


class Scene:
    """The robot, the environment bodies, the task targets and the state label.

    Geometry and camera are sent by :meth:`load`; markers and labels are sent by
    :meth:`load_new` the first time a task or a state shows up in a record.
    """

    def __init__(self, world, geometry: WorldGeometry | None = None):
        """Prepare the scene of ``world``.

        Args:
            world: A :class:`~robocop_dsl.world.World`.
            geometry: Its :class:`WorldGeometry`, when one was made already (before a
                run; see there).
        """
        self.geometry = geometry or WorldGeometry(world)
        self.initial_q = world.initial_configuration()
        corners = self.geometry.corners(self.initial_q)
        lower, upper = corners.min(axis=0), corners.max(axis=0)
        self.label_position = np.array([(lower[0] + upper[0]) / 2, (lower[1] + upper[1]) / 2,
                                        upper[2] + LABEL_HEIGHT])
        self.camera = camera.camera_view(np.vstack([corners, self.label_position]))
        self.tasks: dict = {}       # task name -> kind, for tasks with markers
        self.states: list = []

    def load(self, visualizer) -> None:
        """Send the geometry at the initial configuration and the camera's view."""
        self.geometry.load(visualizer)
        for path, pose in self.geometry.poses(self.initial_q).items():
            visualizer[path].set_transform(pose)
        camera.set_camera(visualizer, *self.camera)

    def load_new(self, visualizer, record) -> None:
        """Send markers and labels for the tasks and state of ``record`` not seen yet."""
        for task in record.tasks:
            if targets.is_drawn(task) and task.name not in self.tasks:
                targets.load_markers(visualizer, task.name, task.kind)
                self.tasks[task.name] = task.kind
        if record.state not in self.states:
            labels.load_label(visualizer, record.state, self.label_position)
            self.states.append(record.state)

    def frame(self, record, body_poses: dict | None = None) -> Frame:
        """Poses and visibilities for a :class:`~robocop_dsl.runtime.records.CycleRecord`.

        Only loaded markers and labels appear; call :meth:`load_new` first.

        Args:
            record: The cycle to draw.
            body_poses: Body name -> 4x4 world pose of every environment body moved so
                far (see :class:`MovedBodies`); default: the record's attached bodies.
        """
        moved = record.body_poses if body_poses is None else body_poses
        poses = self.geometry.poses(record.q, moved)
        enabled = set()
        for task in record.tasks:
            if task.name in self.tasks:
                poses.update(targets.marker_poses(task, self.geometry.body_position))
                enabled.add(task.name)
        visible = {}
        for name in self.tasks:
            for which in (targets.TARGET, targets.REFERENCE):
                path = targets.marker_path(name, which)
                visible[path] = name in enabled and path in poses
        for state in self.states:
            visible[labels.label_path(state)] = state == record.state
        return Frame(record.time, record.state, poses, visible)
