"""Time one control cycle, in one process, against a hand-written floor, Pink and mink.

Problems (identical for every implementation):

- Panda (7 dofs): a body_pose task on the hand (priority 0), a joint_position posture
  task (priority 1, weight 1e-2), joint_kinematic limits (URDF position and velocity
  limits, 10 rad/s^2).
- BAZAR (16 dofs): two body_pose tasks on the tools, the posture task, the joint limits
  and body_velocity limits on both tools (0.5 m/s, 1 rad/s); also with the two
  collision_avoidance constraints below.
- TALOS (30 dofs, base fixed, every joint but the grippers): four body_pose tasks on
  the hands and the feet, the posture task, the joint limits.

Rows: this controller (weighted and strict, its default solver), a hand-written
pinocchio + proxsuite loop solving the weighted problem (the floor, Panda and BAZAR),
Pink's ``solve_ik`` on the weighted problem on DAQP and on ProxQP, and mink's
``solve_ik`` on DAQP (a MuJoCo model of the same world, ``physics_model``); Pink and
mink get the same tasks, costs, gains, damping and limits (the body velocity and
acceleration limits as ``Limit`` classes). Every implementation integrates its own
command from the same start, towards targets 5 cm and 0.2 rad away, the implementations
run in turns of 50 cycles (a shared machine's load falls on all alike); times are the
calling thread's CPU time per cycle (``time.thread_time_ns``). A ratio ``X/this`` is the
median over the turns of the ratio of their medians (above 1: this is faster).

The first cycles: ``--episodes`` fresh starts of every implementation (built untimed,
this controller prepared at the start as a run prepares it before its first cycle:
:meth:`~robocop_dsl.control.Controller.prepare`; then its first 40 cycles timed, in
turns), per cycle the median over the episodes;
printed: the first cycle, the median of cycles 1-39, the ratio ``Pink-daqp/this`` of
those medians, of the first cycle, and the lowest per-cycle one over cycles 1-39 (below
1: a cycle where Pink is faster).

Collision avoidance (BAZAR, strict): the same problem with ``collision_avoidance`` on
the arms vs the workbench and the arms vs themselves (arm vs arm, each arm vs itself;
influence 7 cm), timed from the start posture (no pair within influence once the arms
move off), with the tools held over the workbench side by side (several pairs within
influence, the dampers not binding) and with both tools pressed down on the workbench
(the dampers binding: the QP needs one more iteration), beside the same cycle without
it, in turns; the time added, the pairs checked and the mean number within influence
are printed, and the first cycle with the constraints (the median over
:data:`FIRST_STARTS` fresh controllers): built and stepped at once (``first us``), and
prepared first (``prepared``: :meth:`~robocop_dsl.control.Controller.prepare` plans
the QPs and finds the pairs within influence, as a run does before its first cycle).

With ``--against REVISION``: this controller against the one of a git revision of this
repository (imported beside it under another name, the two run in turns) on the
weighted and strict problems: what a change to the controller costs per cycle.

Usage: ``python bench/controller_cycle.py [--cycles N] [--episodes N] [--only WORLD]
[--against REVISION]``
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import io
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

from robocop_dsl.control import Controller
from robocop_dsl.control.constraints.body_velocity import _DIRECTIONS, INSCRIBED_SCALE
from robocop_dsl.control.solvers.portable import portable_proxsuite
from robocop_dsl.safety.viable import BRAKING_SHARE
from robocop_dsl.world import load_world

proxsuite = portable_proxsuite()
REPO = Path(__file__).resolve().parent.parent
GAIN = 5.0
POSTURE_WEIGHT = 1e-2
DAMPING = 1e-6
ACCELERATION = 10.0
MAX_LINEAR, MAX_ANGULAR = 0.5, 1.0
FIRST_CYCLES = 40
BLOCK = 50
FIRST_STARTS = 7

CASES = {
    "Panda": dict(world="panda/panda_on_table.yaml", group="panda_arm", time_step=0.002,
                  bodies=("panda_hand",), body_velocity=False, start={}),
    "BAZAR": dict(world="bazar/sophia.yaml", group="bazar_upper_joints", time_step=0.005,
                  bodies=("bazar_left_hankamp_tool_object_side",
                          "bazar_right_hankamp_tool_object_side"),
                  body_velocity=True, start={"bazar_arms": [0, 0.4, 0, -1.2, 0, 0.8, 0] * 2}),
    "TALOS": dict(world="talos/talos.yaml", group="talos_body", time_step=0.005,
                  bodies=("gripper_left_base_link", "gripper_right_base_link",
                          "left_sole_link", "right_sole_link"),
                  body_velocity=False, start={}),
}


def start_configuration(case, world):
    """The world's initial configuration with the case's start positions."""
    q0 = world.initial_configuration()
    for group, positions in case["start"].items():
        q0[world.joint_group(group).q_indices] = positions
    return q0


def targets(world, bodies, q):
    """Targets 5 cm and 0.2 rad away from each body's pose at ``q``."""
    shift = pin.SE3(pin.exp3(np.array([0.0, 0.0, 0.2])), np.array([0.05, -0.05, 0.05]))
    return [world.body_pose(body, q) * shift for body in bodies]


def controller(case, world, q0, hierarchy, controller_class=Controller):
    """This project's controller on the case, with its default solver."""
    control = controller_class(world, case["group"], case["time_step"],
                               hierarchy=hierarchy, damping=DAMPING)
    control.add_constraint("joint_kinematic", "limits", case["group"],
                           max_acceleration=ACCELERATION)
    if case["body_velocity"]:
        for body in case["bodies"]:
            control.add_constraint("body_velocity", f"{body}_speed", body,
                                   max_linear=MAX_LINEAR, max_angular=MAX_ANGULAR)
    return control


def ours(case, world, q0, hierarchy, controller_class=Controller, collisions=False):
    """The step of this controller on the case, towards :func:`targets`, prepared at
    ``q0``."""
    return built(case, world, q0, hierarchy, targets(world, case["bodies"], q0),
                 collisions, controller_class, prepared_at=q0)[0]


def built(case, world, q0, hierarchy, goals, avoid, controller_class=Controller,
          prepared_at=None):
    """The problem of the case with body_pose targets ``goals``, with or without the
    collision constraints, prepared for a first cycle at ``prepared_at`` if given
    (:meth:`~robocop_dsl.control.Controller.prepare`, as a run does before its first
    cycle); returns the step and the collision constraints."""
    control = controller(case, world, q0, hierarchy, controller_class)
    constraints = add_collisions(control) if avoid else []
    control.set_auto_enable(True)
    for body, goal in zip(case["bodies"], goals):
        control.add_task("body_pose", body, body, target=goal, gain=GAIN)
    control.add_task("joint_position", "posture", case["group"], priority=1,
                     weight=POSTURE_WEIGHT, gain=GAIN, target=q0[control.state.q_indices])
    if prepared_at is not None:
        control.prepare(prepared_at)
    return (lambda q: control.compute(q).velocity), constraints


def floor(case, world, q0):
    """The weighted problem written directly against pinocchio and proxsuite."""
    model = world.model
    data = model.createData()
    group = world.joint_group(case["group"])
    q_indices, v_indices = np.asarray(group.q_indices), np.asarray(group.v_indices)
    n, dt = group.dofs, case["time_step"]
    frames = [world.body_frame_id(body) for body in case["bodies"]]
    goals = targets(world, case["bodies"], q0)
    posture = q0[q_indices].copy()
    lower_q, upper_q, speed = group.lower, group.upper, group.max_velocity
    rows, row_bound = body_velocity_rows()
    n_in = 26 * len(frames) if case["body_velocity"] else 0
    qp = proxsuite.proxqp.dense.QP(n, 0, n_in, True)
    qp.settings.eps_abs, qp.settings.eps_rel = 1e-9, 0.0
    qp.settings.initial_guess = proxsuite.proxqp.InitialGuess.WARM_START_WITH_PREVIOUS_RESULT
    state = {"previous": np.zeros(n), "initialised": False}

    def braking_speed(distance):
        braking = ACCELERATION * BRAKING_SHARE
        reach = np.sqrt(np.maximum(distance, 0.0) * (2.0 * braking)) - 0.5 * braking * dt
        return np.minimum(distance / dt, np.maximum(reach, 0.0))

    def step(q):
        pin.computeJointJacobians(model, data, q)
        H = np.eye(n) * DAMPING
        g = np.zeros(n)
        C = []
        for frame, goal in zip(frames, goals):
            pose = pin.updateFramePlacement(model, data, frame)
            J = pin.getFrameJacobian(model, data, frame,
                                     pin.LOCAL_WORLD_ALIGNED)[:, v_indices]
            twist = pin.log6(pose.actInv(goal))
            R = pose.rotation
            v = GAIN * np.concatenate((R @ twist.linear, R @ twist.angular))
            H += J.T @ J
            g -= J.T @ v
            if n_in:
                C.append(rows @ J)
        g -= POSTURE_WEIGHT * GAIN * (posture - q[q_indices])
        H[np.diag_indices(n)] += POSTURE_WEIGHT
        qg = q[q_indices]
        previous = state["previous"]
        upper = np.maximum(np.minimum(speed, braking_speed(upper_q - qg)), -speed)
        lower = np.minimum(np.maximum(-speed, -braking_speed(qg - lower_q)), speed)
        upper = np.minimum(upper, previous + ACCELERATION * dt)
        lower = np.maximum(lower, previous - ACCELERATION * dt)
        args = (H, g, None, None) + ((np.vstack(C), -np.tile(row_bound, len(frames)),
                                      np.tile(row_bound, len(frames))) if n_in
                                     else (None, None, None)) + (lower, upper)
        if state["initialised"]:
            qp.update(*args)
        else:
            qp.init(*args)
            state["initialised"] = True
        qp.solve()
        state["previous"] = qp.results.x.copy()
        return state["previous"]

    return step


def body_velocity_rows():
    """The rows and bounds of a body_velocity limit on ``[v, w]`` (LOCAL_WORLD_ALIGNED)."""
    rows = np.zeros((26, 6))
    rows[:13, :3] = _DIRECTIONS
    rows[13:, 3:] = _DIRECTIONS
    bound = np.concatenate((np.full(13, MAX_LINEAR), np.full(13, MAX_ANGULAR)))
    return rows, bound * INSCRIBED_SCALE


def pink_step(case, world, q0, solver):
    """The weighted problem through Pink on ``solver`` (velocities of the whole model)."""
    import pink
    from pink.limits import AccelerationLimit, ConfigurationLimit, Limit, VelocityLimit
    from pink.tasks import FrameTask, PostureTask

    model = world.model
    group = world.joint_group(case["group"])
    dt = case["time_step"]

    class BodyVelocityLimit(Limit):
        def __init__(self, frame):
            self.frame = frame
            self.rows, self.bound = body_velocity_rows()

        def compute_qp_inequalities(self, configuration, dt):
            J = pin.getFrameJacobian(model, configuration.data, self.frame,
                                     pin.LOCAL_WORLD_ALIGNED)
            G = self.rows @ J
            return np.vstack((G, -G)), np.concatenate((self.bound, self.bound)) * dt

    configuration = pink.Configuration(model, model.createData(), q0)
    tasks = []
    for body, goal in zip(case["bodies"], targets(world, case["bodies"], q0)):
        task = FrameTask(body, position_cost=1.0, orientation_cost=1.0, gain=GAIN * dt)
        task.set_target(goal)
        tasks.append(task)
    posture = PostureTask(cost=np.sqrt(POSTURE_WEIGHT), gain=GAIN * dt)
    posture.set_target(q0)
    tasks.append(posture)
    accelerations = np.full(model.nv, 1e6)
    accelerations[group.v_indices] = ACCELERATION
    acceleration = AccelerationLimit(model, accelerations)
    limits = [ConfigurationLimit(model), VelocityLimit(model), acceleration]
    if case["body_velocity"]:
        limits += [BodyVelocityLimit(world.body_frame_id(body)) for body in case["bodies"]]

    def step(q):
        configuration.update(q)
        velocity = pink.solve_ik(configuration, tasks, dt, solver=solver, damping=DAMPING,
                                 limits=limits, safety_break=False)
        acceleration.set_last_integration(velocity, dt)
        return velocity[group.v_indices]

    return step


def mujoco_model(world):
    """The world's MuJoCo model (``physics_model``) without equalities (kinematics
    only), and each joint's ``(qpos address, dof address)``."""
    from robocop_dsl.physics.model import physics_model

    physics = physics_model(world)
    for equality in list(physics.spec.equalities):
        physics.spec.delete(equality)
    return physics.spec.compile(), physics.joints


def mink_step(case, world, q0, solver, mujoco_world):
    """The weighted problem through mink on ``solver`` (a MuJoCo model of the world)."""
    import mink
    import mujoco
    from mink.limits import ConfigurationLimit, Constraint, Limit, VelocityLimit

    mj_model, joints = mujoco_world
    model = world.model
    group = world.joint_group(case["group"])
    dt = case["time_step"]
    q_of = np.array([model.joints[model.getJointId(name)].idx_q for name in joints])
    qpos_of = np.array([address for address, _ in joints.values()])
    dofs = np.array([joints[name][1] for name in group.joints])

    class BodyVelocityLimit(Limit):
        def __init__(self, body):
            self.body = mujoco.mj_name2id(mj_model, mujoco.mjtObj.mjOBJ_BODY, body)
            self.rows, self.bound = body_velocity_rows()
            self.jacobian = np.zeros((6, mj_model.nv))

        def compute_qp_inequalities(self, configuration, dt):
            mujoco.mj_jacBody(mj_model, configuration.data, self.jacobian[:3],
                              self.jacobian[3:], self.body)
            G = self.rows @ self.jacobian
            return Constraint(np.vstack((G, -G)), np.concatenate((self.bound,
                                                                  self.bound)) * dt)

    class AccelerationLimit(Limit):
        def __init__(self):
            self.previous = np.zeros(mj_model.nv)
            self.projection = np.eye(mj_model.nv)[dofs]

        def compute_qp_inequalities(self, configuration, dt):
            upper = (self.previous[dofs] + ACCELERATION * dt) * dt
            lower = (self.previous[dofs] - ACCELERATION * dt) * dt
            return Constraint(np.vstack((self.projection, -self.projection)),
                              np.concatenate((upper, -lower)))

    def qpos(q):
        position = mj_model.qpos0.copy()
        position[qpos_of] = q[q_of]
        return position

    configuration = mink.Configuration(mj_model, qpos(q0))
    tasks = []
    for body, goal in zip(case["bodies"], targets(world, case["bodies"], q0)):
        task = mink.FrameTask(body, "body", position_cost=1.0, orientation_cost=1.0,
                              gain=GAIN * dt)
        task.set_target(mink.SE3.from_matrix(goal.homogeneous))
        tasks.append(task)
    posture = mink.PostureTask(mj_model, cost=np.sqrt(POSTURE_WEIGHT), gain=GAIN * dt)
    posture.set_target(qpos(q0))
    tasks.append(posture)
    speeds = {name: model.velocityLimit[model.joints[model.getJointId(name)].idx_v]
              for name in joints}
    acceleration = AccelerationLimit()
    limits = [ConfigurationLimit(mj_model), VelocityLimit(mj_model, speeds), acceleration]
    if case["body_velocity"]:
        limits += [BodyVelocityLimit(body) for body in case["bodies"]]

    def step(q):
        configuration.update(qpos(q))
        velocity = mink.solve_ik(configuration, tasks, dt, solver=solver, damping=DAMPING,
                                 limits=limits)
        acceleration.previous = velocity
        return velocity[dofs]

    return step


COLLISIONS = (("bazar_arms", "workbench"), ("bazar_arms", "bazar_arms"))
"""The arms vs the workbench; the arms vs themselves: arm vs arm, each arm vs itself."""
PRESSED = (np.array([0.6, 0.25, 0.70]), np.array([0.6, -0.25, 0.70]))
"""Tool targets 4 cm under the workbench surface [m]."""
OVER = (np.array([0.6, 0.08, 0.78]), np.array([0.6, -0.08, 0.78]))
"""Tool targets 4 cm over the workbench surface, 16 cm apart [m]: the tools, the wrists
and the forearms are within influence of the bench or of each other, at rest."""


def add_collisions(control) -> list:
    """The BAZAR collision constraints, added to ``control``."""
    return [control.add_constraint("collision_avoidance", f"clear_{index}", first,
                                   other=second, min_distance=0.02, influence=0.07,
                                   damping=4.0)
            for index, (first, second) in enumerate(COLLISIONS)]


def with_collisions(case, world, q0, goals, avoid, controller_class=Controller,
                    prepared_at=None):
    """The strict problem of :func:`built`, with or without the collision constraints."""
    return built(case, world, q0, "strict", goals, avoid, controller_class, prepared_at)


def first_cycle(case, world, q0, q, goals, prepared: bool, starts: int = FIRST_STARTS) -> float:
    """The median over ``starts`` fresh controllers with the collision constraints of
    their first cycle's thread CPU time [s] at ``q``, each built untimed (and prepared
    at ``q`` when ``prepared``)."""
    times = []
    for _ in range(starts):
        step, _ = with_collisions(case, world, q0, goals, True,
                                  prepared_at=q.copy() if prepared else None)
        start = time.thread_time_ns()
        step(q.copy())
        times.append((time.thread_time_ns() - start) * 1e-9)
    return float(np.median(times))


def settled(case, world, q0, goals, cycles):
    """The posture the collision-avoiding controller reaches towards ``goals``."""
    step, _ = with_collisions(case, world, q0, goals, True)
    group = world.joint_group(case["group"])
    q = q0.copy()
    for _ in range(cycles):
        q[group.q_indices] += step(q) * case["time_step"]
    return q


def postures(case, world):
    """The collision cases: ``(label, posture, body targets)`` of BAZAR, and its start."""
    q0 = start_configuration(case, world)
    down = pin.rpy.rpyToMatrix(0, np.pi, 0)
    over = [pin.SE3(down, p) for p in OVER]
    pressed = [pin.SE3(down, p) for p in PRESSED]
    return q0, (("start posture", q0, targets(world, case["bodies"], q0)),
                ("tools over the workbench, side by side",
                 settled(case, world, q0, over, 2000), over),
                ("tools pressed on the workbench", settled(case, world, q0, pressed, 2000),
                 pressed))


def collision_rows(cycles) -> None:
    case = CASES["BAZAR"]
    world = load_world(case["world"])
    q0, cases = postures(case, world)
    print(f"\n{'BAZAR, strict':<40}{'median us':>10}{'p99 us':>9}{'vs without':>11}"
          f"{'added us':>9}{'pairs':>7}{'near':>6}{'first us':>10}{'prepared':>10}")
    for label, q, goals in cases:
        first = first_cycle(case, world, q0, q, goals, prepared=False)
        ready = first_cycle(case, world, q0, q, goals, prepared=True)
        without = with_collisions(case, world, q0, goals, False)[0]
        step, constraints = with_collisions(case, world, q0, goals, True)
        near = []
        plain, timed = interleaved((without, step), world, case, q, cycles,
                                   after=lambda index: index and near.append(
                                       sum(c.pairs_near for c in constraints)))
        checked = sum(c.pairs_checked for c in constraints)
        base = float(np.median(plain))
        for name, times, ratio, pairs, close, once, warm in (
                (f"{label}, without", plain, 1.0, "", "", "", ""),
                (f"{label}, with", timed, turn_ratio(timed, plain), checked,
                 f"{np.mean(near):.1f}", f"{first * 1e6:.0f}", f"{ready * 1e6:.0f}")):
            added = np.median(times) - base
            print(f"{name:<40}{np.median(times) * 1e6:>10.1f}"
                  f"{np.percentile(times, 99) * 1e6:>9.1f}"
                  f"{ratio:>10.2f}x{added * 1e6:>9.1f}{pairs:>7}{close:>6}{once:>10}"
                  f"{warm:>10}")


def turn_ratio(numerator, denominator) -> float:
    """The median over the turns of the ratio of the turns' medians."""
    return float(np.median(np.median(numerator, axis=1) / np.median(denominator, axis=1)))


def interleaved(steps, world, case, q0, cycles, block=BLOCK, after=lambda index: None):
    """Per-cycle thread CPU times [s] of ``steps`` (turns x ``block`` arrays), each
    integrating its own command from ``q0``, run in turns of ``block`` cycles so that a
    shared machine's load falls on all alike; the first tenth of the turns is left out
    (warm-up). ``after(index)`` is called, untimed, after each cycle of step ``index``."""
    group = world.joint_group(case["group"])
    indices = group.q_indices
    states = [q0.copy() for _ in steps]
    times = [[] for _ in steps]
    clock = time.thread_time_ns
    for _ in range(0, cycles, block):
        for index, (step, q, spent) in enumerate(zip(steps, states, times)):
            for _ in range(block):
                start = clock()
                velocity = step(q)
                spent.append(clock() - start)
                after(index)
                q[indices] += velocity * case["time_step"]
    turns = len(times[0]) // block
    return [np.array(spent).reshape(turns, block)[turns // 10:] * 1e-9 for spent in times]


def first_cycles(builders, world, case, q0, episodes):
    """Per-cycle thread CPU times [s] of the first :data:`FIRST_CYCLES` cycles of fresh
    starts (episodes x cycles arrays): each builder makes a step (untimed), whose first
    cycles are timed; the builders take turns episode by episode."""
    indices = world.joint_group(case["group"]).q_indices
    times = [np.empty((episodes, FIRST_CYCLES)) for _ in builders]
    clock = time.thread_time_ns
    for episode in range(episodes):
        for build, spent in zip(builders, times):
            step, q = build(), q0.copy()
            for cycle in range(FIRST_CYCLES):
                start = clock()
                velocity = step(q)
                spent[episode, cycle] = clock() - start
                q[indices] += velocity * case["time_step"]
    return [spent * 1e-9 for spent in times]


def implementations(name, case, world, q0):
    """``label -> builder`` of every implementation timed on ``case``."""
    mujoco_world = mujoco_model(world)
    builders = {
        "this, weighted": lambda: ours(case, world, q0, "weighted"),
        "this, strict": lambda: ours(case, world, q0, "strict"),
    }
    if case["body_velocity"]:
        builders["this, weighted + coll."] = lambda: ours(case, world, q0, "weighted",
                                                          collisions=True)
        builders["this, strict + coll."] = lambda: ours(case, world, q0, "strict",
                                                        collisions=True)
    if name != "TALOS":
        builders["floor (hand-written)"] = lambda: floor(case, world, q0)
    builders["Pink, daqp"] = lambda: pink_step(case, world, q0, "daqp")
    builders["Pink, proxqp"] = lambda: pink_step(case, world, q0, "proxqp")
    builders["mink, daqp"] = lambda: mink_step(case, world, q0, "daqp", mujoco_world)
    return builders


def episode_table(name, case, world, q0, builders, cycles) -> None:
    labels = list(builders)
    runs = dict(zip(labels, interleaved([build() for build in builders.values()], world,
                                        case, q0, cycles)))
    pink = runs["Pink, daqp"]
    print(f"\n{name}: an episode of {cycles} cycles (dt {case['time_step'] * 1e3:g} ms), "
          "thread CPU time per cycle")
    print(f"{'implementation':<24}{'median us':>10}{'p99 us':>9}{'p99/med':>9}"
          f"{'Pink-daqp/this':>16}")
    for label, times in runs.items():
        median = float(np.median(times))
        print(f"{label:<24}{median * 1e6:>10.1f}{np.percentile(times, 99) * 1e6:>9.1f}"
              f"{np.percentile(times, 99) / median:>9.2f}{turn_ratio(pink, times):>15.2f}x")


def first_table(name, case, world, q0, builders, episodes) -> None:
    runs = dict(zip(builders, first_cycles(list(builders.values()), world, case, q0,
                                           episodes)))
    pink = np.median(runs["Pink, daqp"], axis=0)
    print(f"\n{name}: the first {FIRST_CYCLES} cycles of {episodes} fresh starts "
          "(per cycle, the median over the starts)")
    print(f"{'implementation':<24}{'cycle 0 us':>11}{'1-39 us':>9}{'Pink-daqp/this':>16}"
          f"{'cycle 0':>9}{'lowest 1-39':>13}{'at':>4}")
    for label, times in runs.items():
        per_cycle = np.median(times, axis=0)
        ratios = pink / per_cycle
        worst = 1 + int(np.argmin(ratios[1:]))
        print(f"{label:<24}{per_cycle[0] * 1e6:>11.0f}{np.median(per_cycle[1:]) * 1e6:>9.1f}"
              f"{np.median(pink[1:]) / np.median(per_cycle[1:]):>15.2f}x"
              f"{ratios[0]:>8.2f}x{ratios[worst]:>12.2f}x{worst:>4}")


def against(revision: str, cycles: int) -> None:
    """This controller against the one of git ``revision`` of this repository, imported
    beside it under another name and run in turns with it (:func:`interleaved`) on the
    weighted and strict problems; the ratio is the median over the turns of the ratio
    of their medians."""
    folder = Path(tempfile.mkdtemp())
    archive = subprocess.run(["git", "archive", revision, "robocop_dsl", "robots"],
                             cwd=REPO, capture_output=True, check=True).stdout
    with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
        tar.extractall(folder, filter="data")
    (folder / "robocop_dsl").rename(folder / "robocop_against")
    sys.path.insert(0, str(folder))
    other_control = importlib.import_module("robocop_against.control")
    other_world = importlib.import_module("robocop_against.world")
    print(f"\n{'problem':<52}{'this us':>9}{revision[:10]:>12}{'this/other':>12}")
    rows = []
    for name, case in CASES.items():
        if name == "TALOS":
            continue
        worlds = (load_world(case["world"]), other_world.load_world(case["world"]))
        q0 = start_configuration(case, worlds[0])
        for hierarchy in ("weighted", "strict"):
            rows.append((f"{name}, {hierarchy}", case, worlds[0], q0,
                         (ours(case, worlds[0], q0, hierarchy),
                          ours(case, worlds[1], q0, hierarchy, other_control.Controller))))
    case = CASES["BAZAR"]
    worlds = (load_world(case["world"]), other_world.load_world(case["world"]))
    for label, q, goals in postures(case, worlds[0])[1]:
        rows.append((f"BAZAR, collision avoidance, {label}", case, worlds[0], q,
                     tuple(with_collisions(case, world, q, goals, True, control)[0]
                           for world, control in zip(worlds, (Controller,
                                                              other_control.Controller)))))
    for label, case, world, q, steps in rows:
        this, other = interleaved(steps, world, case, q, cycles)
        print(f"{label:<52}{np.median(this) * 1e6:>9.1f}{np.median(other) * 1e6:>12.1f}"
              f"{turn_ratio(this, other):>11.2f}x")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cycles", type=int, default=2000)
    parser.add_argument("--episodes", type=int, default=15)
    parser.add_argument("--only", choices=list(CASES), help="time one world only")
    parser.add_argument("--against", metavar="REVISION",
                        help="also time this controller against a git revision's")
    args = parser.parse_args(argv)
    solver = inspect.signature(Controller).parameters["solver"].default
    print(f"This controller's default solver: {solver}")
    for name, case in CASES.items():
        if args.only and name != args.only:
            continue
        world = load_world(case["world"])
        q0 = start_configuration(case, world)
        builders = implementations(name, case, world, q0)
        episode_table(name, case, world, q0, builders, args.cycles)
        first_table(name, case, world, q0, builders, args.episodes)
    if not args.only or args.only == "BAZAR":
        collision_rows(args.cycles)
    if args.against:
        against(args.against, args.cycles)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
