"""Time one control cycle, in one process, against a hand-written floor and Pink.

Problems (identical for every implementation):

- BAZAR (16 dofs): two body_pose tasks on the tools (priority 0), a joint_position
  posture task (priority 1, weight 1e-2), joint_kinematic limits (URDF position and
  velocity limits, 10 rad/s^2) and body_velocity limits on both tools (0.5 m/s,
  1 rad/s).
- Panda (7 dofs): a body_pose task on the hand and a posture task, joint limits.

Rows: this controller (weighted and strict, proxqp), a hand-written pinocchio +
proxsuite loop solving the weighted problem (the floor), and Pink's ``solve_ik`` on
the weighted problem (proxqp; the body velocity limit as a Pink ``Limit``). Each run
integrates its own command for ``--cycles`` cycles towards targets 5 cm and 0.2 rad
away; times are per cycle, measured with ``time.perf_counter``.

Collision avoidance (BAZAR, strict): the same problem with ``collision_avoidance`` on
the arms vs the workbench and the arms vs themselves (arm vs arm, each arm vs itself;
influence 7 cm), timed from the start posture (no pair within influence once the arms
move off), with the tools held over the workbench side by side (several pairs within
influence, the dampers not binding) and with both tools pressed down on the workbench
(the dampers binding: the QP needs one more iteration), beside the same cycle without
it, the two run in turns of 50 cycles; the ratio is the median over the turns of the
ratio of their medians (a shared machine's load changes between turns, seldom within
one); the time added, the pairs checked and the mean number within influence are
printed.

With ``--against REVISION``: this controller against the one of a git revision of this
repository (imported beside it under another name, the two run in turns) on the
weighted and strict problems: what a change to the controller costs per cycle.

Usage: ``python bench/controller_cycle.py [--cycles N] [--against REVISION]``
"""

from __future__ import annotations

import argparse
import importlib
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

CASES = {
    "BAZAR": dict(world="bazar/sophia.yaml", group="bazar_upper_joints", time_step=0.005,
                  bodies=("bazar_left_hankamp_tool_object_side",
                          "bazar_right_hankamp_tool_object_side"),
                  body_velocity=True, start={"bazar_arms": [0, 0.4, 0, -1.2, 0, 0.8, 0] * 2}),
    "Panda": dict(world="panda/panda_on_table.yaml", group="panda_arm", time_step=0.002,
                  bodies=("panda_hand",), body_velocity=False, start={}),
}


def targets(world, bodies, q):
    """Targets 5 cm and 0.2 rad away from each body's pose at ``q``."""
    shift = pin.SE3(pin.exp3(np.array([0.0, 0.0, 0.2])), np.array([0.05, -0.05, 0.05]))
    return [world.body_pose(body, q) * shift for body in bodies]


def ours(case, world, q0, hierarchy, controller_class=Controller):
    controller = controller_class(world, case["group"], case["time_step"], "proxqp",
                                  hierarchy, damping=DAMPING)
    controller.add_constraint("joint_kinematic", "limits", case["group"],
                              max_acceleration=ACCELERATION)
    if case["body_velocity"]:
        for body in case["bodies"]:
            controller.add_constraint("body_velocity", f"{body}_speed", body,
                                      max_linear=MAX_LINEAR, max_angular=MAX_ANGULAR)
    controller.set_auto_enable(True)
    for body, target in zip(case["bodies"], targets(world, case["bodies"], q0)):
        controller.add_task("body_pose", body, body, target=target, gain=GAIN)
    controller.add_task("joint_position", "posture", case["group"], priority=1,
                        weight=POSTURE_WEIGHT, gain=GAIN,
                        target=q0[controller.state.q_indices])
    return lambda q: controller.compute(q).velocity


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
    rows = np.zeros((26, 6))
    rows[:13, :3] = _DIRECTIONS
    rows[13:, 3:] = _DIRECTIONS
    row_bound = np.concatenate((np.full(13, MAX_LINEAR), np.full(13, MAX_ANGULAR)))
    row_bound *= INSCRIBED_SCALE
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


def pink_step(case, world, q0):
    """The weighted problem through Pink (velocities of the whole model)."""
    import pink
    from pink.limits import AccelerationLimit, ConfigurationLimit, Limit, VelocityLimit
    from pink.tasks import FrameTask, PostureTask

    model = world.model
    group = world.joint_group(case["group"])
    dt = case["time_step"]

    class BodyVelocityLimit(Limit):
        def __init__(self, frame):
            self.frame = frame
            self.rows = np.zeros((26, 6))
            self.rows[:13, :3] = _DIRECTIONS
            self.rows[13:, 3:] = _DIRECTIONS
            bound = np.concatenate((np.full(13, MAX_LINEAR), np.full(13, MAX_ANGULAR)))
            self.bound = bound * INSCRIBED_SCALE

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
        velocity = pink.solve_ik(configuration, tasks, dt, solver="proxqp", damping=DAMPING,
                                 limits=limits, safety_break=False)
        acceleration.set_last_integration(velocity, dt)
        return velocity[group.v_indices]

    return step


COLLISIONS = (("bazar_arms", "workbench"), ("bazar_arms", "bazar_arms"))
"""The arms vs the workbench; the arms vs themselves: arm vs arm, each arm vs itself."""
PRESSED = (np.array([0.6, 0.25, 0.70]), np.array([0.6, -0.25, 0.70]))
"""Tool targets 4 cm under the workbench surface [m]."""
OVER = (np.array([0.6, 0.08, 0.78]), np.array([0.6, -0.08, 0.78]))
"""Tool targets 4 cm over the workbench surface, 16 cm apart [m]: the tools, the wrists
and the forearms are within influence of the bench or of each other, at rest."""


def with_collisions(case, world, q0, goals, avoid, controller_class=Controller):
    """The strict problem of ``ours`` with body_pose targets ``goals``, with or without
    the collision constraints; returns the step and the collision constraints."""
    controller = controller_class(world, case["group"], case["time_step"], "proxqp",
                                  "strict", damping=DAMPING)
    controller.add_constraint("joint_kinematic", "limits", case["group"],
                              max_acceleration=ACCELERATION)
    for body in case["bodies"]:
        controller.add_constraint("body_velocity", f"{body}_speed", body,
                                  max_linear=MAX_LINEAR, max_angular=MAX_ANGULAR)
    constraints = [controller.add_constraint("collision_avoidance", f"clear_{index}", first,
                                             other=second, min_distance=0.02, influence=0.07,
                                             damping=4.0)
                   for index, (first, second) in enumerate(COLLISIONS) if avoid]
    controller.set_auto_enable(True)
    for body, goal in zip(case["bodies"], goals):
        controller.add_task("body_pose", body, body, target=goal, gain=GAIN)
    controller.add_task("joint_position", "posture", case["group"], priority=1,
                        weight=POSTURE_WEIGHT, gain=GAIN,
                        target=q0[controller.state.q_indices])
    return (lambda q: controller.compute(q).velocity), constraints


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
    q0 = world.initial_configuration()
    for group, positions in case["start"].items():
        q0[world.joint_group(group).q_indices] = positions
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
          f"{'added us':>9}{'pairs':>7}{'near':>6}")
    for label, q, goals in cases:
        without = with_collisions(case, world, q0, goals, False)[0]
        step, constraints = with_collisions(case, world, q0, goals, True)
        near = []
        plain, timed = interleaved((without, step), world, case, q, cycles,
                                   after=lambda index: index and near.append(
                                       sum(c.pairs_near for c in constraints)))
        checked = sum(c.pairs_checked for c in constraints)
        base = float(np.median(plain))
        turns = np.median(timed, axis=1) / np.median(plain, axis=1)
        for name, times, ratio, pairs, close in (
                (f"{label}, without", plain, 1.0, "", ""),
                (f"{label}, with", timed, float(np.median(turns)), checked,
                 f"{np.mean(near):.1f}")):
            added = np.median(times) - base
            print(f"{name:<40}{np.median(times) * 1e6:>10.1f}"
                  f"{np.percentile(times, 99) * 1e6:>9.1f}"
                  f"{ratio:>10.2f}x{added * 1e6:>9.1f}{pairs:>7}{close:>6}")


def interleaved(steps, world, case, q0, cycles, block=50, after=lambda index: None):
    """Per-cycle times of ``steps`` (turns x ``block`` arrays), each integrating its own
    command from ``q0``, run in turns of ``block`` cycles so that a shared machine's load
    falls on all alike; the first tenth of the turns is left out (warm-up).
    ``after(index)`` is called, untimed, after each cycle of step ``index``."""
    group = world.joint_group(case["group"])
    states = [q0.copy() for _ in steps]
    times = [[] for _ in steps]
    for _ in range(0, cycles, block):
        for index, (step, q, spent) in enumerate(zip(steps, states, times)):
            for _ in range(block):
                start = time.perf_counter()
                velocity = step(q)
                spent.append(time.perf_counter() - start)
                after(index)
                q[group.q_indices] += velocity * case["time_step"]
    turns = len(times[0]) // block
    return [np.array(spent).reshape(turns, block)[turns // 10:] for spent in times]


def measure(step, world, case, q0, cycles):
    group = world.joint_group(case["group"])
    q = q0.copy()
    times = np.empty(cycles)
    for index in range(cycles):
        start = time.perf_counter()
        velocity = step(q)
        times[index] = time.perf_counter() - start
        q[group.q_indices] += velocity * case["time_step"]
    return times[cycles // 10:]


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
        worlds = (load_world(case["world"]), other_world.load_world(case["world"]))
        q0 = worlds[0].initial_configuration()
        for group, positions in case["start"].items():
            q0[worlds[0].joint_group(group).q_indices] = positions
        for hierarchy in ("weighted", "strict"):
            rows.append((f"{name}, {hierarchy}", case, worlds[0], q0,
                         (ours(case, worlds[0], q0, hierarchy),
                          ours(case, worlds[1], q0, hierarchy, other_control.Controller))))
    case = CASES["BAZAR"]
    worlds = (load_world(case["world"]), other_world.load_world(case["world"]))
    for label, q, goals in postures(case, worlds[0])[1]:
        rows.append((f"BAZAR, collision avoidance, {label}", case, worlds[0], q,
                     tuple(with_collisions(case, world, q, goals, True, controller)[0]
                           for world, controller in zip(worlds, (Controller,
                                                                 other_control.Controller)))))
    for label, case, world, q, steps in rows:
        this, other = interleaved(steps, world, case, q, cycles)
        ratio = float(np.median(np.median(this, axis=1) / np.median(other, axis=1)))
        print(f"{label:<52}{np.median(this) * 1e6:>9.1f}{np.median(other) * 1e6:>12.1f}"
              f"{ratio:>11.2f}x")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cycles", type=int, default=3000)
    parser.add_argument("--against", metavar="REVISION",
                        help="also time this controller against a git revision's")
    args = parser.parse_args(argv)
    print(f"{'world':<7}{'implementation':<20}{'median us':>10}{'p99 us':>9}"
          f"{'vs floor':>10}{'Pink/this':>11}")
    for name, case in CASES.items():
        world = load_world(case["world"])
        q0 = world.initial_configuration()
        for group, positions in case["start"].items():
            q0[world.joint_group(group).q_indices] = positions
        runs = {"floor (hand-written)": floor(case, world, q0),
                "this, weighted": ours(case, world, q0, "weighted"),
                "this, strict": ours(case, world, q0, "strict"),
                "Pink": pink_step(case, world, q0)}
        stats = {label: measure(step, world, case, q0, args.cycles)
                 for label, step in runs.items()}
        medians = {label: float(np.median(t)) for label, t in stats.items()}
        for label, t in stats.items():
            ratio = medians[label] / medians["floor (hand-written)"]
            pink = (f"{medians['Pink'] / medians[label]:.2f}x"
                    if label.startswith("this") else "")
            print(f"{name:<7}{label:<20}{medians[label] * 1e6:>10.1f}"
                  f"{np.percentile(t, 99) * 1e6:>9.1f}{ratio:>9.2f}x{pink:>11}")
    collision_rows(args.cycles)
    if args.against:
        against(args.against, args.cycles)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
