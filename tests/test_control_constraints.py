"""Constraints hold over randomised runs; infeasible or non-finite inputs give a flagged hold."""

import numpy as np
import pinocchio as pin
import pytest

from robocop_dsl.control import Controller, InvalidParameter
from robocop_dsl.control.constraints.body_velocity import _DIRECTIONS, INSCRIBED_SCALE

TOOLS = ("bazar_left_hankamp_tool_object_side", "bazar_right_hankamp_tool_object_side")
ACCELERATION = 4.0
MAX_VELOCITY = 1.0
MAX_LINEAR, MAX_ANGULAR = 0.3, 0.8


def limited_bazar(world, hierarchy):
    controller = Controller(world, "bazar_upper_joints", 0.005, hierarchy=hierarchy)
    controller.add_constraint("joint_kinematic", "limits", "bazar_upper_joints",
                              max_velocity=MAX_VELOCITY, max_acceleration=ACCELERATION)
    for tool in TOOLS:
        controller.add_constraint("body_velocity", tool, tool, max_linear=MAX_LINEAR,
                                  max_angular=MAX_ANGULAR)
    return controller


@pytest.mark.parametrize("seed", range(6))
def test_limits_hold_over_random_runs(bazar, seed):
    """No joint leaves its range or exceeds its velocity or acceleration; tool speeds hold."""
    rng = np.random.default_rng(seed)
    controller = limited_bazar(bazar, "strict" if seed % 2 else "weighted")
    group = bazar.joint_group("bazar_upper_joints")
    arms = bazar.joint_group("bazar_arms")
    q = bazar.initial_configuration()
    posture = controller.add_task("joint_position", "posture", "bazar_arms", priority=1,
                                  gain=20, target=rng.uniform(arms.lower - 0.3, arms.upper + 0.3))
    posture.enable()
    for tool in TOOLS:
        goal = bazar.body_pose(tool, q) * pin.SE3(pin.exp3(rng.normal(0, 0.8, 3)),
                                                  rng.normal(0, 0.3, 3))
        task = controller.add_task("body_pose", tool, tool, target=goal, gain=20)
        task.enable()
    previous = np.zeros(group.dofs)
    for cycle in range(600):
        result = controller.compute(q)
        assert result.solved, result.reason
        velocity = result.velocity
        assert np.all(np.abs(velocity) <= MAX_VELOCITY + 1e-7)
        assert np.all(np.abs(velocity - previous) / 0.005 <= ACCELERATION + 1e-5)
        for tool in TOOLS:
            twist = bazar.body_jacobian(tool, q)[:, group.v_indices] @ velocity
            assert np.linalg.norm(twist[:3]) <= MAX_LINEAR + 1e-7
            assert np.linalg.norm(twist[3:]) <= MAX_ANGULAR + 1e-7
        q[group.q_indices] += velocity * 0.005
        assert np.all(q[group.q_indices] >= group.lower - 1e-9)
        assert np.all(q[group.q_indices] <= group.upper + 1e-9)
        previous = velocity


def test_speed_polytope_is_inside_the_ball():
    """The 13-direction polytope with the inscribed scale never exceeds the speed limit."""
    rng = np.random.default_rng(0)
    directions = rng.normal(size=(2000, 3))
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    largest = INSCRIBED_SCALE / np.max(np.abs(directions @ _DIRECTIONS.T), axis=1)
    assert np.max(largest) <= 1.0 + 1e-12
    assert np.min(largest) >= 0.886


def test_per_axis_body_velocity_limit(panda):
    """A 3-vector limit bounds each axis of the reference frame."""
    controller = Controller(panda, "panda_arm", 0.002, hierarchy="weighted")
    controller.add_constraint("body_velocity", "hand", "panda_hand",
                              max_linear=[0.01, 0.02, np.inf])
    task = controller.add_task("body_velocity", "push", "panda_hand",
                               target=[1.0, 1.0, 0.01, 0.0, 0.0, 0.0])
    task.enable()
    q = panda.initial_configuration()
    velocity = controller.compute(q).velocity
    twist = panda.body_jacobian("panda_hand", q)[:, panda.joint_group("panda_arm").v_indices]
    linear = (twist @ velocity)[:3]
    assert abs(linear[0]) <= 0.01 + 1e-8 and abs(linear[1]) <= 0.02 + 1e-8


def test_infeasible_constraints_relax_body_velocity_first(panda):
    """Constraints without a common solution relax the body velocity bound, never the
    position limit: the joint is driven back, the cycle flagged as failed."""
    controller = Controller(panda, "panda_arm", 0.002)
    q = panda.initial_configuration()
    joint = panda.joint_group("panda_arm")
    forced = joint.lower.copy()
    forced[1] = q[joint.q_indices][1] + 0.2
    controller.add_constraint("joint_kinematic", "forced", "panda_arm", min_position=forced)
    controller.add_constraint("body_velocity", "still", "panda_hand", max_linear=0.0)
    result = controller.compute(q)
    assert not result.solved and controller.failed and result.status == "relaxed"
    assert [r.constraint for r in result.relaxations] == ["body_velocity 'still'"]
    assert result.velocity[1] == pytest.approx(joint.max_velocity[1])
    controller.constraint("still").disable()
    assert controller.compute(q).solved and not controller.failed


def test_joint_constraints_meet_in_one_table(panda):
    """Two joint constraints meet: a joint below one's range is driven back at the
    other's speed limit."""
    controller = Controller(panda, "panda_arm", 0.002)
    q = panda.initial_configuration()
    joint = panda.joint_group("panda_arm")
    forced = joint.lower.copy()
    forced[0] = q[joint.q_indices][0] + 0.5
    controller.add_constraint("joint_kinematic", "forced", "panda_arm", min_position=forced)
    controller.add_constraint("joint_kinematic", "slow", "panda_joint1", max_velocity=0.01)
    result = controller.compute(q)
    assert result.solved and result.velocity[0] == pytest.approx(0.01)


def test_non_finite_inputs_are_refused(panda):
    """NaN or infinite states and targets give a flagged zero command, never an exception."""
    controller = Controller(panda, "panda_arm", 0.002)
    task = controller.add_task("joint_position", "arm", "panda_arm")
    task.enable()
    q = panda.initial_configuration()
    bad = q.copy()
    bad[2] = np.nan
    result = controller.compute(bad)
    assert result.failed and "configuration" in result.reason
    assert np.all(result.velocity == 0.0)
    dq = np.zeros(panda.model.nv)
    dq[0] = np.inf
    assert controller.compute(q, dq).failed
    task.target = [0, 0, np.inf, 0, 0, 0, 0]
    result = controller.compute(q)
    assert result.failed and "target" in result.reason
    task.target = np.zeros(7)
    assert controller.compute(q).solved


def test_constraint_parameters(panda):
    """Defaults come from the URDF; configure validates and repr is readable."""
    controller = Controller(panda, "panda_arm", 0.002)
    limits = controller.add_constraint("joint_kinematic", "limits", "panda_arm")
    group = panda.joint_group("panda_arm")
    np.testing.assert_array_equal(limits.max_velocity, group.max_velocity)
    np.testing.assert_array_equal(limits.parameters()["min_position"], group.lower)
    limits.configure(max_velocity=0.5)
    assert np.all(limits.max_velocity == 0.5)
    with pytest.raises(InvalidParameter) as error:
        limits.configure(max_velocity=-1.0)
    assert error.value.parameter == "max_velocity"
    assert repr(limits).startswith("JointKinematicConstraint('limits', group='panda_arm'")
