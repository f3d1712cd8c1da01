"""Each task type converges to its target on the Panda and on BAZAR; frame conventions."""

import numpy as np
import pinocchio as pin
import pytest

from robocop_dsl.control import (CURRENT, BodyTarget, Controller, InvalidParameter,
                                 OTGInterpolator, UnknownName)

LEFT_TOOL = "bazar_left_hankamp_tool_object_side"
ARMS_MID_RANGE = [0, 0.4, 0, -1.2, 0, 0.8, 0] * 2


def controller_for(world, group, time_step=0.005, **options):
    controller = Controller(world, group, time_step, **options)
    controller.add_constraint("joint_kinematic", "limits", group)
    return controller


def run(controller, q, until, cycles=4000):
    """Integrate the command from ``q`` until ``until()`` holds; returns the final q."""
    q = q.copy()
    for _ in range(cycles):
        result = controller.compute(q)
        assert result.solved, result.reason
        q[controller.state.q_indices] += result.velocity * controller.time_step
        controller.update_state(q)
        if until():
            break
    return q


def shifted(world, body, q, translation, rotation=(0.0, 0.0, 0.0)):
    return world.body_pose(body, q) * pin.SE3(pin.rpy.rpyToMatrix(*rotation),
                                             np.array(translation, dtype=float))


def test_joint_position_converges_on_bazar(bazar):
    """joint_position on both arms reaches its target within 1e-4 rad through otg."""
    controller = controller_for(bazar, "bazar_upper_joints")
    target = np.array([0, 0.25, 0, -2, 0, 0.7, 0] * 2) + 0.1
    arms = controller.add_task("joint_position", "arms", "bazar_arms", target=target,
                               interpolator=OTGInterpolator(1.0, 1.0), gain=10)
    arms.enable()
    q = run(controller, bazar.initial_configuration(), lambda: arms.reached and arms.error < 1e-4)
    assert arms.reached
    assert np.max(np.abs(q[bazar.joint_group("bazar_arms").q_indices] - target)) < 1e-4


@pytest.mark.parametrize("world_name", ["panda", "bazar"])
def test_body_pose_converges(world_name, request):
    """body_pose reaches a pose 5 cm / 0.3 rad away: < 0.1 mm and < 1 mrad."""
    world = request.getfixturevalue(world_name)
    group, body = (("panda_arm", "panda_hand") if world_name == "panda"
                   else ("bazar_upper_joints", LEFT_TOOL))
    controller = controller_for(world, group)
    q0 = world.initial_configuration()
    if world_name == "bazar":
        q0[world.joint_group("bazar_arms").q_indices] = ARMS_MID_RANGE
    goal = shifted(world, body, q0, [0.05, -0.03, 0.04], [0.2, -0.1, 0.15])
    task = controller.add_task("body_pose", "tool", body, target=goal, gain=10,
                               interpolator=OTGInterpolator(0.2, 0.5, max_angular_velocity=1.0,
                                                            max_angular_acceleration=2.0))
    task.enable()
    q = run(controller, q0, lambda: task.reached and task.position_error < 5e-5
            and task.orientation_error < 5e-4)
    pose = world.body_pose(body, q)
    assert np.linalg.norm(pose.translation - goal.translation) < 1e-4
    assert np.linalg.norm(pin.log3(pose.rotation.T @ goal.rotation)) < 1e-3


def test_body_position_and_orientation_converge(panda):
    """body_position (< 0.1 mm) and body_orientation (< 1 mrad) reach their targets."""
    controller = controller_for(panda, "panda_arm", hierarchy="weighted")
    q0 = panda.initial_configuration()
    goal = shifted(panda, "panda_hand", q0, [0.04, 0.05, -0.03], [0.0, 0.3, -0.2])
    position = controller.add_task("body_position", "position", "panda_hand",
                                   target=goal.translation, gain=10)
    orientation = controller.add_task("body_orientation", "orientation", "panda_hand",
                                      target=goal.rotation, gain=10,
                                      interpolator=OTGInterpolator(1.0, 2.0))
    position.enable()
    orientation.enable()
    q = run(controller, q0, lambda: position.error < 5e-5 and orientation.error < 5e-4)
    pose = panda.body_pose("panda_hand", q)
    assert np.linalg.norm(pose.translation - goal.translation) < 1e-4
    assert np.linalg.norm(pin.log3(pose.rotation.T @ goal.rotation)) < 1e-3
    assert position.orientation_error == 0.0 and orientation.position_error == 0.0


def test_velocity_tasks_are_tracked(panda):
    """joint_velocity and body_velocity commands achieve their target velocities."""
    controller = controller_for(panda, "panda_arm", hierarchy="weighted")
    q = panda.initial_configuration()
    joints = controller.add_task("joint_velocity", "joints", "panda_arm",
                                 target=[0.1, -0.1, 0.05, 0.0, 0.1, 0.0, -0.2])
    joints.enable()
    result = controller.compute(q)
    np.testing.assert_allclose(result.velocity, joints.target, atol=1e-5)
    joints.disable()
    twist = np.array([0.05, -0.02, 0.03, 0.0, 0.1, -0.1])
    body = controller.add_task("body_velocity", "hand", "panda_hand", target=twist)
    body.enable()
    result = controller.compute(q)
    jacobian = panda.body_jacobian("panda_hand", q)[:, panda.joint_group("panda_arm").v_indices]
    np.testing.assert_allclose(jacobian @ result.velocity, twist, atol=1e-5)


def test_reference_frame_convention(panda):
    """Targets and velocities of a body task are expressed in its reference body's frame."""
    controller = controller_for(panda, "panda_arm", hierarchy="weighted")
    q0 = panda.initial_configuration()
    table = panda.body_pose("table", q0)
    in_table = np.array([0.1, 0.15, 0.35])
    task = controller.add_task("body_position", "hand", "panda_hand", reference="table",
                               target=in_table, gain=10)
    task.enable()
    q = run(controller, q0, lambda: task.error < 5e-5)
    expected = table.act(in_table)
    assert np.linalg.norm(panda.body_pose("panda_hand", q).translation - expected) < 1e-4
    moving = controller.add_task("body_velocity", "relative", "panda_hand",
                                 reference="panda_link4", target=np.zeros(6))
    jacobian = controller.state.jacobian(moving.body_id, moving.reference_id)
    link4 = panda.body_pose("panda_link4", q)
    hand = panda.body_pose("panda_hand", q)
    velocity = np.full(7, 0.1)
    v_indices = panda.joint_group("panda_arm").v_indices
    step = 1e-6
    q_next = q.copy()
    q_next[panda.joint_group("panda_arm").q_indices] += velocity * step
    relative = link4.actInv(hand)
    relative_next = panda.body_pose("panda_link4", q_next).actInv(
        panda.body_pose("panda_hand", q_next))
    linear = (relative_next.translation - relative.translation) / step
    angular = pin.log3(relative_next.rotation @ relative.rotation.T) / step
    np.testing.assert_allclose(jacobian @ velocity, np.concatenate((linear, angular)), atol=1e-5)
    assert v_indices.shape == (7,)


def test_tracking_a_body_with_offset(panda):
    """A body target follows the tracked body's pose, with an offset in the reference frame."""
    controller = controller_for(panda, "panda_arm")
    task = controller.add_task("body_pose", "hand", "panda_hand", gain=10,
                               target=BodyTarget("target_point", pin.SE3.Identity()))
    task.target = BodyTarget("target_point", [0.0, 0.0, 0.05])
    task.enable()
    q = run(controller, panda.initial_configuration(),
            lambda: task.position_error < 5e-5 and task.orientation_error < 5e-4)
    goal = panda.body_pose("target_point", q)
    hand = panda.body_pose("panda_hand", q)
    np.testing.assert_allclose(hand.translation, goal.translation + [0, 0, 0.05], atol=1e-4)
    np.testing.assert_allclose(hand.rotation, goal.rotation, atol=1e-3)


def test_current_target_holds(panda):
    """target CURRENT keeps the pose the task had when it started."""
    controller = controller_for(panda, "panda_arm", hierarchy="weighted")
    q0 = panda.initial_configuration()
    hold = controller.add_task("body_pose", "hold", "panda_hand", target=CURRENT, gain=10)
    push = controller.add_task("joint_velocity", "push", "panda_arm", target=np.full(7, 0.2),
                               weight=1e-4)
    hold.enable()
    push.enable()
    q = run(controller, q0, lambda: False, cycles=200)
    assert hold.position_error < 1e-4
    assert np.linalg.norm(q - q0) > 1e-3


def test_task_errors_carry_data(panda):
    """Wrong bodies, groups and targets raise errors naming what is valid."""
    controller = controller_for(panda, "panda_arm")
    with pytest.raises(UnknownName) as error:
        controller.add_task("body_pose", "hand", "panda_hnd")
    assert "panda_hand" in error.value.available and "did you mean" in str(error.value)
    with pytest.raises(InvalidParameter) as error:
        controller.add_task("joint_position", "arm", "panda_arm", target=[0.0] * 6)
    assert error.value.parameter == "target"
    task = controller.add_task("body_pose", "hand", "panda_hand")
    with pytest.raises(UnknownName):
        task.target = "nowhere"
    assert repr(task).startswith("BodyPoseTask('hand', body='panda_hand', reference='world'")
