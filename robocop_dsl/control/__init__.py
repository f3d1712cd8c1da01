"""Kinematic QP whole-body controller: tasks, constraints, interpolators, feedback loops.

Build a :class:`Controller` over a joint group of a world, add tasks and constraints,
and call :meth:`Controller.compute` every period with the model's configuration; it
returns the group's joint-velocity command (:class:`ControlResult`).
"""

from __future__ import annotations

from .constraints import CONSTRAINTS, BodyVelocityConstraint, Constraint, JointKinematicConstraint
from .controller import HIERARCHIES, Controller
from .exceptions import (ControlError, DuplicateName, InvalidParameter,
                         JointGroupOutsideController, UnknownKind, UnknownName, UnknownSolver)
from .feedback import (FEEDBACK_LOOPS, FeedbackLoop, PIDFeedback, ProportionalFeedback,
                       make_feedback_loop)
from .interpolators import (INTERPOLATORS, CubicInterpolator, Interpolator, LinearInterpolator,
                            NoInterpolator, OTGInterpolator, QuinticInterpolator,
                            make_interpolator)
from .kinematics import Kinematics
from .results import ControlResult, LevelResult, Timings
from .solvers import QPSolver, QuadraticProgram, available_solvers, make_solver
from .spatial import CURRENT, BodyTarget
from .state import ControlState
from .tasks import (TASKS, BodyForceTask, BodyOrientationTask, BodyPoseTask, BodyPositionTask,
                    BodyVelocityTask, JointPositionTask, JointVelocityTask, Task, TaskSample)

__all__ = [
    "BodyForceTask", "BodyOrientationTask", "BodyPoseTask", "BodyPositionTask", "BodyTarget",
    "BodyVelocityConstraint", "BodyVelocityTask", "CONSTRAINTS", "CURRENT", "Constraint",
    "ControlError", "ControlResult", "ControlState", "Controller", "CubicInterpolator",
    "DuplicateName", "FEEDBACK_LOOPS", "FeedbackLoop", "HIERARCHIES", "INTERPOLATORS",
    "Interpolator", "InvalidParameter", "JointGroupOutsideController",
    "JointKinematicConstraint", "JointPositionTask", "JointVelocityTask", "Kinematics",
    "LevelResult", "LinearInterpolator", "NoInterpolator", "OTGInterpolator", "PIDFeedback",
    "ProportionalFeedback", "QPSolver", "QuadraticProgram", "QuinticInterpolator", "TASKS",
    "Task", "TaskSample", "Timings", "UnknownKind", "UnknownName", "UnknownSolver", "available_solvers",
    "make_feedback_loop", "make_interpolator", "make_solver",
]
