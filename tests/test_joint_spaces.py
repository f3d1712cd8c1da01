"""Joint quantities are angles, one per dof, whatever the joint type: the Kinova Jaco2's
continuous joints (pinocchio's cos/sin coordinates), a mimic finger, a floating base
outside the controlled group; velocity limits never above the URDF's."""

import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pandas as pd
import pinocchio as pin
import pytest
from arm_reaching import problems, run_ours, run_pink

from robocop_dsl.control import Controller
from robocop_dsl.world import load_world

REPO = Path(__file__).resolve().parent.parent
ROBOTS = "example-robot-data/robots"
TIME_STEP = 0.005


@pytest.fixture(scope="module")
def jaco():
    """The Jaco2 on a table (kinova/jaco.yaml): nq 9, nv 6."""
    return load_world("kinova/jaco.yaml")


def robocop(*args):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", *map(str, args)],
                          cwd=REPO, capture_output=True, text=True)


def integrate(world, group, q, command, time_step=TIME_STEP):
    motion = np.zeros(world.model.nv)
    motion[group.v_indices] = command * time_step
    return pin.integrate(world.model, q, motion)


def test_the_jaco_has_continuous_joints(jaco):
    model = jaco.model
    group = jaco.joint_group("jaco_arm")
    assert (model.nq, model.nv, group.dofs, len(group.q_indices)) == (9, 6, 6, 9)
    assert group.space.continuous.tolist() == [True, False, False, True, False, True]
    assert np.isinf(group.lower[group.space.continuous]).all()


def test_initial_postures_are_angles(jaco):
    """``initial:`` gives one angle per dof; positions read back in (-pi, pi]."""
    group = jaco.joint_group("jaco_arm")
    positions = group.positions(jaco.initial_configuration())
    np.testing.assert_allclose(positions, [4.8 - 2 * np.pi, 2.92, 1.0, 4.2 - 2 * np.pi,
                                           1.44, 1.32])


def test_limits_alone_keep_the_jaco_still(jaco):
    """With the limits constraint and no task, nothing moves: no joint is read as
    outside its range (joint 2 was driven through its 5.46 rad limit)."""
    group = jaco.joint_group("jaco_arm")
    rng = np.random.default_rng(3)
    margin = 0.05
    low = np.where(np.isfinite(group.lower), group.lower + margin, -np.pi)
    high = np.where(np.isfinite(group.upper), group.upper - margin, np.pi)
    for _ in range(5):
        controller = Controller(jaco, "jaco_arm", TIME_STEP)
        controller.add_constraint("joint_kinematic", "limits", "jaco_arm",
                                  max_acceleration=5.0)
        q = jaco.initial_configuration()
        q[group.q_indices] = group.space.coordinates(rng.uniform(low, high))
        start = group.positions(q)
        for _ in range(200):
            command = controller.compute(q).velocity
            assert np.all(command == 0.0)
            q = integrate(jaco, group, q, command)
        np.testing.assert_array_equal(group.positions(q), start)


def test_limits_hold_on_the_way_to_a_target_past_them(jaco):
    """A posture target beyond joint 2's upper limit stops at the limit."""
    group = jaco.joint_group("jaco_arm")
    controller = Controller(jaco, "jaco_arm", TIME_STEP)
    controller.add_constraint("joint_kinematic", "limits", "jaco_arm",
                              max_acceleration=5.0)
    q = jaco.initial_configuration()
    target = group.positions(q) + [0, 3.0, 0, 0, 0, 0]
    task = controller.add_task("joint_position", "posture", "jaco_arm", target=target,
                               interpolator="none", gain=5)
    task.enable()
    for _ in range(2000):
        q = integrate(jaco, group, q, controller.compute(q).velocity)
        assert group.positions(q)[1] <= group.upper[1] + 1e-9
    assert group.positions(q)[1] == pytest.approx(group.upper[1], abs=1e-3)


def test_a_posture_target_at_the_current_posture_commands_nothing(jaco):
    group = jaco.joint_group("jaco_arm")
    controller = Controller(jaco, "jaco_arm", TIME_STEP)
    controller.add_constraint("joint_kinematic", "limits", "jaco_arm")
    q = jaco.initial_configuration()
    task = controller.add_task("joint_position", "posture", "jaco_arm",
                               target=group.positions(q), gain=10)
    task.enable()
    result = controller.compute(q)
    assert result.solved
    np.testing.assert_allclose(result.velocity, 0.0, atol=1e-12)
    assert task.error == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("interpolator", [{"spec": "none"},
                                          {"spec": "otg", "max_velocity": 0.5,
                                           "max_acceleration": 1.0}])
def test_a_continuous_joint_turns_the_shortest_way(jaco, interpolator):
    """From 10 deg, a target of 350 deg is reached by turning -20 deg."""
    group = jaco.joint_group("jaco_arm")
    controller = Controller(jaco, "jaco_arm", TIME_STEP)
    controller.add_constraint("joint_kinematic", "limits", "jaco_arm")
    q = jaco.initial_configuration()
    start = group.positions(q)
    start[0] = np.radians(10)
    q[group.q_indices] = group.space.coordinates(start)
    target = start.copy()
    target[0] = np.radians(350)
    task = controller.add_task("joint_position", "posture", "jaco_arm", target=target,
                               gain=5)
    task.set_interpolator(**interpolator)
    task.enable()
    controller.kinematics.update(q)
    assert task.error == pytest.approx(np.radians(20))
    travelled = 0.0
    for _ in range(1500):
        command = controller.compute(q).velocity
        travelled += command[0] * TIME_STEP
        q = integrate(jaco, group, q, command)
        assert np.radians(-10.5) <= travelled + np.radians(10) <= np.radians(10) + 1e-9
    assert travelled == pytest.approx(np.radians(-20), abs=1e-4)
    assert group.positions(q)[0] == pytest.approx(np.radians(-10), abs=1e-4)
    assert task.error < 1e-4


def test_the_jaco_reaches_as_often_as_pink(jaco):
    """Random reachable tool poses (it reached 1 in 50 when continuous joints were
    read as angles)."""
    pytest.importorskip("pink")
    group = jaco.joint_group("jaco_arm")
    tool = "j2s6s200_end_effector"
    cases = problems(jaco, group, tool, 10, seed=11)
    ours = [run_ours(jaco, group, tool, case) for case in cases]
    pink = [run_pink(jaco, group, tool, case) for case in cases]
    assert sum(o.reached for o in ours) >= max(9, sum(o.reached for o in pink))
    assert sum(o.violations for o in ours) == 0


def test_the_jaco_mission_runs_to_success(tmp_path):
    """missions/jaco_reach.mission checks and runs to its success final, its log
    finite."""
    mission = REPO / "missions" / "jaco_reach.mission"
    assert robocop("check", mission).returncode == 0
    run = robocop("run", mission, "--log", tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr
    log = pd.read_parquet(tmp_path / "timeseries.parquet")
    assert len(log) > 100
    assert np.isfinite(log.filter(like="command.").to_numpy()).all()


def test_a_floating_base_outside_the_group(tmp_path):
    """TALOS on a floating base (nq = nv + 1): its arm's posture task reads its arm."""
    path = tmp_path / "talos.yaml"
    path.write_text(textwrap.dedent(f"""
        models:
          - path: {ROBOTS}/talos_data/robots/talos_reduced.urdf
            joint: {{type: floating}}
        joint_groups:
          arm: [arm_left_1_joint, arm_left_2_joint, arm_left_3_joint, arm_left_4_joint,
                arm_left_5_joint, arm_left_6_joint, arm_left_7_joint]
        initial:
          world_to_base_link: [0, 0, 1.0, 0, 0, 0.5]
          arm: [0.3, 0.4, -0.5, -1.0, 0, 0, 0.1]
    """))
    world = load_world(path)
    group = world.joint_group("arm")
    q = world.initial_configuration()
    base = world.body_pose("base_link", q)
    np.testing.assert_allclose(base.translation, [0, 0, 1.0], atol=1e-12)
    assert pin.log3(base.rotation)[2] == pytest.approx(0.5)
    np.testing.assert_allclose(group.positions(q), [0.3, 0.4, -0.5, -1.0, 0, 0, 0.1])
    controller = Controller(world, "arm", TIME_STEP)
    controller.add_constraint("joint_kinematic", "limits", "arm")
    target = group.positions(q) + 0.1
    task = controller.add_task("joint_position", "posture", "arm", target=target, gain=10,
                               interpolator="none")
    task.enable()
    for _ in range(600):
        q = integrate(world, group, q, controller.compute(q).velocity)
    np.testing.assert_allclose(group.positions(q), target, atol=1e-6)
    assert world.body_pose("base_link", q).isApprox(base)


def test_a_mimic_finger_follows_its_joint(panda):
    """The Panda's gripper group has one dof: the mimic finger follows it."""
    group = panda.joint_group("panda_gripper")
    assert (group.dofs, group.joints) == (1, ("panda_finger_joint1",))
    q = panda.initial_configuration()
    q[group.q_indices] = group.space.coordinates([0.03])
    np.testing.assert_allclose(group.positions(q), [0.03])
    left = panda.body_pose("panda_leftfinger", q).translation
    right = panda.body_pose("panda_rightfinger", q).translation
    assert np.linalg.norm(left - right) == pytest.approx(0.06, abs=1e-9)


def test_velocity_limits_never_exceed_the_urdfs(panda, tmp_path):
    """``max_velocity = 10 rad/s`` on the Panda (URDF: 2.175 to 2.61 rad/s): ``check``
    warns that the URDF's limit wins, and the run never commands more than it."""
    mission = tmp_path / "fast.mission"
    mission.write_text(textwrap.dedent("""
        mission fast "A posture move far away, as fast as allowed."
        world "panda/panda_on_table.yaml"
        constraint limits: joint_kinematic(panda_arm) {
            max_velocity     = 10 rad/s
            max_acceleration = 20 rad/s^2
        }
        task posture: joint_position(panda_arm) {
            interpolator = none
            feedback     = proportional(gain = 50)
        }
        state go {
            enter {
                enable posture
                posture.target = [1.5, 0.5, -1.5, -1.0, 1.5, 2.5, -1.5] rad
            }
            when posture.error < 1 deg -> done
            when elapsed > 10 s -> failed
        }
        final done
        final failed: failure
    """).lstrip())
    check = robocop("check", mission)
    assert check.returncode == 0
    assert "warning[limit-above-urdf]" in check.stdout
    assert "the URDF's limit wins" in check.stdout
    assert ":4:24:" in check.stdout
    run = robocop("run", mission, "--log", tmp_path / "log")
    assert run.returncode == 0, run.stdout + run.stderr
    log = pd.read_parquet(tmp_path / "log" / "timeseries.parquet")
    group = panda.joint_group("panda_arm")
    commands = log[[f"command.{j}" for j in group.joints]].to_numpy()
    assert (np.abs(commands) <= group.max_velocity + 1e-9).all()
    assert (np.abs(commands).max(axis=0) > group.max_velocity - 1e-6).sum() >= 4
