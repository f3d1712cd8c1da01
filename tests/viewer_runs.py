"""Runs for the viewer tests: the real pickup mission, and a synthetic run on the real
BAZAR world (BAZAR's arms move between two postures, a pose task and a position task
get enabled and disabled, the part gets attached to the left tool and released, with
the control cycle of the world's controller)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from robocop_dsl.runtime import RunLogger, load_mission
from robocop_dsl.runtime.records import CycleRecord, TaskView

PICKUP = Path(__file__).resolve().parent.parent / "missions" / "pickup.mission"

TIME_STEP = 0.005               # [s], the world's controller time step
STATES = (("goto_initial_pose", 0.0), ("approach", 0.5), ("grasp", 1.0), ("lift", 1.5),
          ("release", 1.8))
DURATION = 2.0                  # [s]
REACH = np.array([0.3, 0.6, 0.0, -1.2, 0.0, 0.9, 0.0, -0.3, 0.6, 0.0, -1.2, 0.0, 0.9, 0.0])
LEFT_TOOL = "bazar_left_hankamp_tool_object_side"
RIGHT_TOOL = "bazar_right_hankamp_tool_object_side"


def state_at(time: float) -> str:
    """The synthetic run's state at ``time`` [s]."""
    return [name for name, start in STATES if time >= start - 1e-12][-1]


def configuration(world, time: float) -> np.ndarray:
    """The world's configuration at ``time``: arms from the initial posture to REACH."""
    q = world.initial_configuration()
    arms = world.joint_group("bazar_arms")
    blend = 0.5 - 0.5 * np.cos(np.pi * min(time / DURATION, 1.0))
    q[arms.q_indices] = (1 - blend) * q[arms.q_indices] + blend * REACH
    return q


def synthetic_run(world, duration: float = DURATION, step: float = TIME_STEP) -> list:
    """Cycle records of the synthetic run, one per control cycle."""
    records = []
    pickup = world.body_pose("pickup_point", world.initial_configuration()).homogeneous
    part_offset = None
    for cycle in range(int(round(duration / step)) + 1):
        time = cycle * step
        q = configuration(world, time)
        state = state_at(time)
        tool = world.body_pose(LEFT_TOOL, q).homogeneous
        tasks = []
        if state in ("approach", "grasp"):
            target = pickup.copy()
            target[2, 3] += 0.1 if state == "approach" else 0.0
            tasks.append(TaskView("left_tool", "pose", LEFT_TOOL, 0.01, target, tool))
        if state in ("grasp", "lift", "release"):
            right = world.body_pose(RIGHT_TOOL, q).translation
            tasks.append(TaskView("right_point", "position", RIGHT_TOOL, 0.02,
                                  np.array([0.5, -0.3, 1.0]), right.copy()))
        tasks.append(TaskView("arms", "joint", None, 0.1, REACH.copy(), q[:14].copy()))
        body_poses = {}
        if state == "lift":
            if part_offset is None:
                part = world.body_pose("part_body", q).homogeneous
                part_offset = np.linalg.inv(tool) @ part
            body_poses["part_body"] = tool @ part_offset
        records.append(CycleRecord(cycle=cycle, time=time, state=state, q=q,
                                   positions=q.copy(), command=np.zeros(len(q)),
                                   solved=True, tasks=tuple(tasks), body_poses=body_poses))
    return records


def pickup_run(make_observers, log_folder=None) -> tuple:
    """Run the pickup mission headless, as fast as it goes.

    Args:
        make_observers: Called with the mission's world before the run; returns the
            observers to add.
        log_folder: Where to log the run, if anywhere.

    Returns:
        The run's result and the observers.
    """
    mission = load_mission(PICKUP)
    runner = mission.runner()
    observers = make_observers(mission.world)
    if log_folder is not None:
        runner.add_observer(RunLogger(log_folder, runner.joint_names))
    for observer in observers:
        runner.add_observer(observer)
    return runner.run(), observers
