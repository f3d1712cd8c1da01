"""Priorities, solvers and the controller's API."""

import numpy as np
import pinocchio as pin
import pytest

from robocop_dsl.control import (Controller, DuplicateName, Kinematics, UnknownKind,
                                 UnknownName, UnknownSolver, available_solvers)
from robocop_dsl.world import load_world

TOOLS = ("bazar_left_hankamp_tool_object_side", "bazar_right_hankamp_tool_object_side")
ARMS_MID_RANGE = [0, 0.4, 0, -1.2, 0, 0.8, 0] * 2


def bazar_problem(world, hierarchy="strict", solver="proxqp", posture=True):
    controller = Controller(world, "bazar_upper_joints", 0.005, solver, hierarchy)
    controller.add_constraint("joint_kinematic", "limits", "bazar_upper_joints",
                              max_acceleration=10.0)
    controller.set_auto_enable(True)
    q = world.initial_configuration()
    q[world.joint_group("bazar_arms").q_indices] = ARMS_MID_RANGE
    for tool in TOOLS:
        controller.add_constraint("body_velocity", tool + "_speed", tool, max_linear=0.5,
                                  max_angular=1.0)
        goal = world.body_pose(tool, q) * pin.SE3(pin.exp3(np.array([0.1, 0.2, -0.1])),
                                                  np.array([0.03, -0.02, 0.04]))
        controller.add_task("body_pose", tool, tool, target=goal, gain=5)
    if posture:
        controller.add_task("joint_position", "posture", "bazar_upper_joints", priority=1,
                            weight=1e-2, gain=5, target=np.zeros(16))
    return controller, q


def task_velocities(world, controller, q, velocity):
    v_indices = world.joint_group("bazar_upper_joints").v_indices
    return np.concatenate([world.body_jacobian(tool, q)[:, v_indices] @ velocity
                           for tool in TOOLS])


def test_strict_lower_level_never_degrades_higher(bazar):
    """A priority-0 task's achieved velocity is unchanged by lower-priority tasks."""
    with_posture, q = bazar_problem(bazar)
    without_posture, _ = bazar_problem(bazar, posture=False)
    for cycle in range(50):
        full = with_posture.compute(q)
        alone = without_posture.compute(q)
        assert full.solved and alone.solved
        np.testing.assert_allclose(task_velocities(bazar, with_posture, q, full.velocity),
                                   task_velocities(bazar, without_posture, q, alone.velocity),
                                   atol=1e-6)
        assert len(full.levels) == 2 and full.levels[1].tasks == ("posture",)
        without_posture.state.previous_command = full.velocity
        q[with_posture.state.q_indices] += full.velocity * 0.005
    assert not np.allclose(full.velocity, alone.velocity, atol=1e-4)


@pytest.mark.parametrize("hierarchy, solver", [("weighted", "quadprog"), ("weighted", "daqp"),
                                               ("strict", "daqp")])
def test_second_solver_agrees(bazar, hierarchy, solver):
    """A second backend gives the proxqp command to 1e-5."""
    reference, q = bazar_problem(bazar, hierarchy)
    other, _ = bazar_problem(bazar, hierarchy, solver)
    for _ in range(20):
        expected = reference.compute(q)
        got = other.compute(q)
        assert got.solved
        np.testing.assert_allclose(got.velocity, expected.velocity, atol=1e-5)
        q[reference.state.q_indices] += expected.velocity * 0.005
        other.state.previous_command = expected.velocity


def test_weighted_mode_solves_one_qp(panda):
    """weighted puts every task in one QP whose residual is reported."""
    controller = Controller(panda, "panda_arm", 0.002, hierarchy="weighted")
    controller.set_auto_enable(True)
    controller.add_task("body_position", "hand", "panda_hand", target=[0.4, 0.1, 1.0])
    controller.add_task("joint_position", "posture", "panda_arm", priority=3, weight=0.1)
    result = controller.compute(panda.initial_configuration())
    assert result.solved and len(result.levels) == 1
    assert result.levels[0].tasks == ("hand", "posture") and result.residuals[0] > 0.0
    assert result.timings.total >= result.timings.solve > 0.0
    assert len(controller.problems) == 1 and controller.problems[0].validate().size[0] == 7


def test_unknown_solver_lists_installed(panda):
    """An unknown solver name raises an error listing the installed backends."""
    with pytest.raises(UnknownSolver) as error:
        Controller(panda, "panda_arm", 0.002, solver="proxqpp")
    assert set(error.value.available) == set(available_solvers())
    assert "proxqp" in str(error.value) and "did you mean 'proxqp'" in str(error.value)


def test_enable_disable_and_auto_enable(panda):
    """Tasks start disabled and constraints enabled; set_auto_enable changes both."""
    controller = Controller(panda, "panda_arm", 0.002)
    task = controller.add_task("joint_position", "posture", "panda_arm")
    limits = controller.add_constraint("joint_kinematic", "limits", "panda_arm")
    assert not task.enabled and limits.enabled
    controller.set_auto_enable(False)
    assert not controller.add_constraint("body_velocity", "slow", "panda_hand").enabled
    controller.set_auto_enable(True)
    assert controller.add_task("body_pose", "hand", "panda_hand").enabled
    assert controller.task("posture") is task and controller.constraint("limits") is limits
    with pytest.raises(UnknownName) as error:
        controller.task("postur")
    assert error.value.available == ("hand", "posture")
    with pytest.raises(DuplicateName):
        controller.add_task("joint_position", "posture", "panda_arm")
    with pytest.raises(UnknownKind) as error:
        controller.add_task("joint_pose", "x", "panda_arm")
    assert "joint_position" in error.value.available
    assert "tasks=1/2 enabled" in repr(controller)


def test_reached_and_reset(panda):
    """reached follows the interpolator; reset restarts it from the current state."""
    controller = Controller(panda, "panda_arm", 0.002)
    q = panda.initial_configuration()
    target = q[controller.state.q_indices] + 0.05
    task = controller.add_task("joint_position", "posture", "panda_arm", target=target, gain=20)
    task.set_interpolator("linear", duration=0.1)
    task.enable()
    assert not task.reached
    for _ in range(50):
        q[controller.state.q_indices] += controller.compute(q).velocity * 0.002
    assert task.reached and task.error < 1e-2
    task.reset()
    assert not task.reached
    controller.compute(q)
    assert not task.reached and task.interpolator().elapsed == pytest.approx(0.002)


def test_from_world_and_shared_kinematics(bazar):
    """from_world reads the qp_controller processor; a Kinematics can be shared."""
    kinematics = Kinematics(bazar)
    controller = Controller.from_world(bazar, kinematics=kinematics)
    assert controller.time_step == 0.005 and controller.hierarchy == "strict"
    assert controller.kinematics is kinematics and controller.joint_group.dofs == 16
    controller.update_state(bazar.initial_configuration())
    assert kinematics.distance("pickup_point", "drop_point") > 0.0


def test_attach_moves_a_body_with_the_tool():
    """An attached body follows its new parent; detach fixes it where it is."""
    world = load_world("bazar/sophia.yaml")
    controller = Controller.from_world(world)
    kinematics = controller.kinematics
    tool = "bazar_left_hankamp_tool_object_side"
    q = world.initial_configuration()
    kinematics.update(q)
    before = kinematics.body_pose("part_body")
    kinematics.attach("part_body", tool)
    kinematics.update(q)
    np.testing.assert_allclose(kinematics.body_pose("part_body").homogeneous,
                               before.homogeneous, atol=1e-12)
    relative = kinematics.body_pose(tool).actInv(kinematics.body_pose("part_body"))
    q[world.joint_group("bazar_left_arm").q_indices] += 0.2
    kinematics.update(q)
    moved = kinematics.body_pose(tool).actInv(kinematics.body_pose("part_body"))
    np.testing.assert_allclose(moved.homogeneous, relative.homogeneous, atol=1e-12)
    assert not np.allclose(kinematics.body_pose("part_body").translation, before.translation)
    held = kinematics.body_pose("part_body")
    kinematics.detach("part_body")
    q[world.joint_group("bazar_left_arm").q_indices] -= 0.2
    kinematics.update(q)
    np.testing.assert_allclose(kinematics.body_pose("part_body").homogeneous,
                               held.homogeneous, atol=1e-12)
