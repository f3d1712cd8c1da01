"""Tasks: motion objectives of the controller, one type per module."""

from __future__ import annotations

from .base import Task, TaskSample
from .body import BodyTask
from .body_force import BodyForceTask
from .body_orientation import BodyOrientationTask
from .body_pose import BodyPoseTask
from .body_position import BodyPositionTask
from .body_velocity import BodyVelocityTask
from .gaze import GazeTask
from .joint_position import JointPositionTask
from .joint_velocity import JointVelocityTask

TASKS: dict[str, type[Task]] = {
    cls.kind: cls for cls in (JointPositionTask, JointVelocityTask, BodyPositionTask,
                              BodyOrientationTask, BodyPoseTask, BodyVelocityTask, GazeTask,
                              BodyForceTask)
}

__all__ = [
    "BodyForceTask", "BodyOrientationTask", "BodyPoseTask", "BodyPositionTask", "BodyTask",
    "BodyVelocityTask", "GazeTask", "JointPositionTask", "JointVelocityTask", "TASKS", "Task",
    "TaskSample",
]
