"""The controller's damping: no chatter toward a target out of reach, no measurable
slow-down toward reachable ones, and ProxQP's settings accepting every problem DAQP
accepts. Counts cycles of a simulated loop, never time."""

import textwrap

import numpy as np
import pytest

from robocop_dsl.control import Controller, ProportionalFeedback
from robocop_dsl.diagnostics import DiagnosticError
from robocop_dsl.world import load_world

OUT_OF_REACH = np.array([1.5, 0.8, 1.5])


def hand_controller(world, target, **options):
    control = Controller.from_world(world, **options)
    control.add_constraint("joint_kinematic", "limits", "panda_arm", max_acceleration=100.0)
    kind = "body_position" if isinstance(target, np.ndarray) else "body_pose"
    task = control.add_task(kind, "hand", "panda_hand", target=target,
                            feedback=ProportionalFeedback(gain=5.0))
    task.enable()
    return control, task


def simulate(control, task, q, cycles, until=None):
    """The commands [rad/s] of ``cycles`` cycles, or the cycles until the task error is
    below ``until``."""
    indices = control.joint_group.q_indices
    commands = []
    for cycle in range(cycles):
        result = control.compute(q)
        assert result.solved, result.reason
        q[indices] += result.velocity * control.time_step
        commands.append(result.velocity)
        if until is not None and task.error < until:
            return cycle + 1
    return np.array(commands)


def test_no_chatter_toward_a_target_out_of_reach(panda):
    """Stretched toward a point 0.9 m beyond reach, the arm comes to rest with the
    default damping; without the Levenberg-Marquardt term the same arm keeps moving at
    rad/s with commands changing sign."""
    def last_second(**options):
        control, task = hand_controller(panda, OUT_OF_REACH, **options)
        commands = simulate(control, task, panda.initial_configuration(), 1600)[-200:]
        flips = (np.sign(commands[1:]) != np.sign(commands[:-1])) & (
            np.abs(commands[1:]) > 0.01) & (np.abs(commands[:-1]) > 0.01)
        return np.abs(commands).max(), int(flips.sum()), task.error

    still, still_flips, still_error = last_second()
    restless, restless_flips, restless_error = last_second(lm_damping=0.0)
    assert restless > 1.0 and restless_flips > 10
    assert still < 0.05 and still_flips == 0
    assert still_error == pytest.approx(restless_error, abs=0.01)


def test_reachable_targets_converge_as_fast(panda):
    """Toward random reachable hand poses, the default damping reaches 1 mm within 2 %
    of the cycles the undamped controller takes, for every target."""
    rng = np.random.default_rng(3)
    group = panda.joint_group("panda_arm")
    for _ in range(5):
        start = panda.initial_configuration()
        start[group.q_indices] += rng.normal(0, 0.3, group.dofs)
        goal = start.copy()
        goal[group.q_indices] += rng.normal(0, 0.3, group.dofs)
        pose = panda.body_pose("panda_hand", goal)
        cycles = [simulate(*hand_controller(panda, pose, **options), start.copy(), 2000,
                           until=1e-3) for options in ({}, {"lm_damping": 0.0})]
        assert isinstance(cycles[1], int) and isinstance(cycles[0], int)
        assert cycles[0] <= 1.02 * cycles[1]


UR5 = """
models:
  - path: example-robot-data/robots/ur_description/urdf/ur5_robot.urdf
    namespace: ur5
joint_groups:
  arm: [ur5_shoulder_pan_joint, ur5_shoulder_lift_joint, ur5_elbow_joint,
        ur5_wrist_1_joint, ur5_wrist_2_joint, ur5_wrist_3_joint]
processors:
  controller:
    type: qp_controller
    options: {joint_group: arm, time_step: 5ms, lm_damping: 0}
"""


@pytest.fixture(scope="module")
def ur5(tmp_path_factory):
    path = tmp_path_factory.mktemp("ur5") / "ur5.yaml"
    path.write_text(textwrap.dedent(UR5))
    return load_world(path)


def test_proxqp_solves_what_daqp_solves_near_singularities(ur5):
    """At 300 random UR5 states, a third of them on the elbow or wrist singularity, the
    controller's QPs (pose task above a posture task, joint and tool limits, no
    Levenberg-Marquardt term) are solved by ProxQP whenever DAQP solves them, to the
    same command."""
    rng = np.random.default_rng(7)
    group = ur5.joint_group("arm")
    for _ in range(300):
        q = ur5.initial_configuration()
        q[group.q_indices] = rng.uniform(-np.pi, np.pi, group.dofs)
        if rng.uniform() < 0.35:
            q[group.q_indices[[2, 4]]] = rng.normal(0, 1e-4, 2)
        goal = q.copy()
        goal[group.q_indices] += rng.normal(0, 0.5, group.dofs)
        commands = {}
        for solver in ("daqp", "proxqp"):
            control = Controller.from_world(ur5, solver=solver)
            control.add_constraint("joint_kinematic", "limits", "arm", max_acceleration=10.0)
            control.add_constraint("body_velocity", "tool", "ur5_tool0", max_linear=0.5,
                                   max_angular=1.0)
            control.add_task("body_pose", "tool", "ur5_tool0",
                             target=ur5.body_pose("ur5_tool0", goal), gain=5.0).enable()
            control.add_task("joint_position", "posture", "arm", target=goal[group.q_indices],
                             priority=1).enable()
            result = control.compute(q)
            commands[solver] = result.velocity if result.solved else None
        if commands["daqp"] is not None:
            assert commands["proxqp"] is not None
            np.testing.assert_allclose(commands["proxqp"], commands["daqp"], atol=1e-4)


@pytest.mark.parametrize("option, value, message", [
    ("lm_damping", -1, "must be a number >= 0, not -1"),
    ("damping", 0, "must be a number > 0, not 0"),
    ("damping", ".nan", "must be a number > 0, not nan"),
])
def test_damping_options_are_checked_where_written(tmp_path, option, value, message):
    path = tmp_path / "w.yaml"
    path.write_text(textwrap.dedent(UR5).replace("lm_damping: 0", f"{option}: {value}"))
    with pytest.raises(DiagnosticError) as error:
        load_world(path)
    text = str(error.value)
    assert "wrong-option" in text and message in text and "w.yaml:11:" in text
