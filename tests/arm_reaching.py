"""Reaching random poses with the fixed-base arms of example-robot-data: this controller
and Pink on the same targets, from the same starts, for the same number of cycles.

Each problem is a start configuration drawn in the arm's joint ranges and a target
pose of its tool: the pose forward kinematics gives for a configuration a little away
from the start (so the target is reachable). Both controllers run a pure differential
inverse kinematics: one pose task (proportional gain :data:`GAIN`, no interpolation)
under the URDF's position and velocity limits, integrated with ``pin.integrate``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from robocop_dsl.control import Controller
from robocop_dsl.world import load_world

FIXTURES = Path(__file__).resolve().parent / "fixtures" / "arms"

ROBOTS = "example-robot-data/robots/"
ARMS = {
    "UR5": (FIXTURES / "ur5.yaml", "arm", "tool0", "ur_description/urdf/ur5_robot.urdf"),
    "UR10": (FIXTURES / "ur10.yaml", "arm", "tool0", "ur_description/urdf/ur10_robot.urdf"),
    "Panda": ("panda/panda_on_table.yaml", "panda_arm", "panda_hand",
              "panda_description/urdf/panda.urdf"),
    "Kinova Jaco2": ("kinova/jaco.yaml", "jaco_arm", "j2s6s200_end_effector",
                     "kinova_description/robots/kinova.urdf"),
    "xArm7": (FIXTURES / "xarm7.yaml", "arm", "link_eef", "xarm_description/urdf/xarm7.urdf"),
    "Z1": (FIXTURES / "z1.yaml", "arm", "link06", "z1_description/urdf/z1.urdf"),
    "TALOS left arm": (FIXTURES / "talos.yaml", "arm", "gripper_left_base_link",
                       "talos_data/robots/talos_reduced.urdf"),
    "TIAGo arm": (FIXTURES / "tiago.yaml", "arm", "arm_tool_link",
                  "tiago_description/robots/tiago.urdf"),
    "Baxter left arm": (FIXTURES / "baxter.yaml", "left_arm", "left_gripper",
                        "baxter_description/urdf/baxter.urdf"),
    "Baxter right arm": (FIXTURES / "baxter.yaml", "right_arm", "right_gripper",
                         "baxter_description/urdf/baxter.urdf"),
}
"""Arm name -> (world file, joint group, tool body, URDF along the robots path)."""

TIME_STEP = 0.02        # [s]
CYCLES = 100
GAIN = 10.0             # [1/s]
SPREAD = 0.4            # [rad or m] standard deviation of the target's joint offsets
MARGIN = 0.05           # share of each joint range kept clear of its limits
POSITION_TOLERANCE = 1e-3          # [m]
ANGLE_TOLERANCE = np.radians(1.0)  # [rad]
LIMIT_SLACK = 1e-6      # [rad or m]


@dataclass
class Problem:
    """A start configuration (the world's ``q``) and a target pose of the tool."""

    start: np.ndarray
    target: pin.SE3


@dataclass
class Outcome:
    """How a controller ended one problem."""

    reached: bool
    violations: int
    finite: bool


def arm(name: str) -> tuple:
    """The world, joint group and tool body of the arm ``name``."""
    path, group, tool, _ = ARMS[name]
    world = load_world(path)
    return world, world.joint_group(group), tool


def problems(world, group, tool: str, count: int, seed: int) -> list[Problem]:
    """``count`` reachable problems for ``group``'s ``tool``, drawn from ``seed``."""
    rng = np.random.default_rng(seed)
    lower = np.where(np.isfinite(group.lower), group.lower, -np.pi)
    upper = np.where(np.isfinite(group.upper), group.upper, np.pi)
    margin = MARGIN * (upper - lower)
    low, high = lower + margin, upper - margin
    found = []
    for _ in range(count):
        start = rng.uniform(low, high)
        goal = np.clip(start + rng.normal(0.0, SPREAD, group.dofs), low, high)
        q_start, q_goal = (configuration(world, group, p) for p in (start, goal))
        found.append(Problem(q_start, world.body_pose(tool, q_goal)))
    return found


def configuration(world, group, positions: np.ndarray) -> np.ndarray:
    """The world's initial configuration with ``group`` at ``positions`` (one per dof)."""
    q = world.initial_configuration()
    q[group.q_indices] = group.space.coordinates(positions)
    return q


def reached(pose: pin.SE3, target: pin.SE3) -> bool:
    """Whether ``pose`` is within the position and angle tolerances of ``target``."""
    error = pin.log6(pose.actInv(target)).vector
    return bool(np.linalg.norm(pose.rotation @ error[:3]) < POSITION_TOLERANCE
                and np.linalg.norm(error[3:]) < ANGLE_TOLERANCE)


def run_ours(world, group, tool: str, problem: Problem) -> Outcome:
    """This controller: a ``body_pose`` task under ``joint_kinematic`` limits."""
    controller = Controller(world, group.name, TIME_STEP)
    controller.add_constraint("joint_kinematic", "limits", group.name)
    task = controller.add_task("body_pose", "tool", tool, target=problem.target,
                               interpolator="none", gain=GAIN)
    task.enable()
    model = world.model
    q = problem.start.copy()
    violations, finite = 0, True
    motion = np.zeros(model.nv)
    for _ in range(CYCLES):
        command = controller.compute(q).velocity
        finite &= bool(np.isfinite(command).all())
        motion[group.v_indices] = command * TIME_STEP
        q = pin.integrate(model, q, motion)
        violations += _violations(group, group.positions(q))
    return Outcome(reached(world.body_pose(tool, q), problem.target), violations, finite)


def run_pink(world, group, tool: str, problem: Problem) -> Outcome:
    """Pink: a ``FrameTask`` under its configuration and velocity limits, on the
    world's model reduced to the group's joints (the others locked at the start). A
    QP Pink finds no solution to ends the problem, unreached."""
    import pink
    from pink.exceptions import NoSolutionFound
    from pink.limits import ConfigurationLimit, VelocityLimit
    from pink.tasks import FrameTask

    model = world.model
    locked = [j for j in range(1, model.njoints) if model.names[j] not in group.joints]
    reduced = pin.buildReducedModel(model, locked, problem.start)
    configuration = pink.Configuration(reduced, reduced.createData(),
                                       pin.neutral(reduced))
    names = [reduced.names[j] for j in range(1, reduced.njoints)]
    start = dict(zip(group.joints, _split(group, group.positions(problem.start))))
    q = pin.integrate(reduced, pin.neutral(reduced), np.concatenate([start[n] for n in names]))
    configuration.update(q)
    task = FrameTask(tool, position_cost=1.0, orientation_cost=1.0, gain=GAIN * TIME_STEP)
    task.set_target(problem.target)
    limits = [ConfigurationLimit(reduced), VelocityLimit(reduced)]
    order = {n: i for i, n in enumerate(names)}
    columns = np.concatenate([np.arange(reduced.idx_vs[order[n] + 1],
                                        reduced.idx_vs[order[n] + 1] + reduced.nvs[order[n] + 1])
                              for n in group.joints])
    violations, finite = 0, True
    for _ in range(CYCLES):
        try:
            velocity = pink.solve_ik(configuration, [task], TIME_STEP, solver="proxqp",
                                     limits=limits, safety_break=False)
        except NoSolutionFound:
            return Outcome(False, violations, finite)
        finite &= bool(np.isfinite(velocity).all())
        configuration.update(configuration.integrate(velocity, TIME_STEP))
        positions = pin.difference(reduced, pin.neutral(reduced), configuration.q)[columns]
        violations += _violations(group, positions)
    frame = reduced.getFrameId(tool, pin.FrameType.BODY)
    pose = configuration.get_transform_frame_to_world(reduced.frames[frame].name)
    return Outcome(reached(pose, problem.target), violations, finite)


def _split(group, positions: np.ndarray) -> list:
    """The group's positions cut per joint."""
    sizes = np.asarray(group.space.model.nvs[1:])
    return np.split(positions, np.cumsum(sizes)[:-1])


def _violations(group, positions: np.ndarray) -> int:
    return int(np.count_nonzero((positions < group.lower - LIMIT_SLACK)
                                | (positions > group.upper + LIMIT_SLACK)))
