"""The safety layer: promises the controller keeps every cycle and during every stop.

1. joint velocities within the stricter of the URDF's and the mission's limits, and
   accelerations within ``max_acceleration``;
2. joint positions within the URDF's (and the mission's) position limits;
3. every enabled ``collision_avoidance`` pair at least ``min_distance`` apart.

- :mod:`~robocop_dsl.safety.limits`: the joint limits table of a controller;
- :mod:`~robocop_dsl.safety.viable`: viable bounds, the approach speed from which the
  robot still stops before a limit or an obstacle;
- :mod:`~robocop_dsl.safety.joint_box`: the joint limits table as the cycle's velocity
  box;
- :mod:`~robocop_dsl.safety.relaxation`: the order in which an infeasible cycle is
  relaxed, and the relaxation QP;
- :mod:`~robocop_dsl.safety.braking`: the stop as a QP;
- :mod:`~robocop_dsl.safety.robot_state`: the driver's state, validated every cycle;
- :mod:`~robocop_dsl.safety.robot_state`: the driver's state checked every cycle;
- :mod:`~robocop_dsl.safety.report`: the smallest clearances and largest excesses of a
  run;
- :mod:`~robocop_dsl.safety.guard`: what a run's loop asks of the layer every cycle.
"""

from __future__ import annotations

from .guard import RunGuard
from .braking import AT_REST, SETTLING_TIME, BrakingProgram, stop_cycles
from .joint_box import JointBox
from .limits import JointLimits, joint_limits
from .relaxation import Relaxation, Relaxer, RowGroup, acceleration_box
from .report import SafetyReport
from .robot_state import RobotStateCheck, RobotStateError
from .viable import BRAKING_SHARE, approach_speed, distance_rate_bounds, viable_speed

__all__ = [
    "AT_REST", "BRAKING_SHARE", "BrakingProgram", "JointBox", "JointLimits", "Relaxation",
    "Relaxer", "RobotStateCheck", "RunGuard", "RobotStateError", "RowGroup", "SETTLING_TIME",
    "SafetyReport", "acceleration_box", "approach_speed", "distance_rate_bounds",
    "joint_limits", "stop_cycles", "viable_speed",
]
