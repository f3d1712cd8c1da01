"""Every fixed-base arm of example-robot-data, loaded through the world loader: its
kinematics is pinocchio's, and this controller reaches random reachable poses at least
as often as Pink does, never past a joint limit, with finite commands."""

import numpy as np
import pinocchio as pin
import pytest
from arm_reaching import (ARMS, ROBOTS, arm, configuration, problems, run_ours,
                          run_pink)

from robocop_dsl.world.paths import resolve

TARGETS = 20


def direct_model(name):
    """The arm's URDF loaded by pinocchio alone."""
    urdf = resolve(ROBOTS + ARMS[name][3], None)
    return pin.buildModelFromUrdf(str(urdf))


@pytest.mark.parametrize("name", list(ARMS))
def test_forward_kinematics_is_pinocchios(name):
    """At random joint positions, the tool's pose relative to the body the arm is
    mounted on is the one pinocchio computes from the URDF directly."""
    world, group, tool = arm(name)
    model = direct_model(name)
    data = model.createData()
    mount = world.joint(group.joints[0]).parent
    rng = np.random.default_rng(7)
    for _ in range(5):
        positions = rng.uniform(-np.pi, np.pi, group.dofs)
        q = configuration(world, group, positions)
        ours = world.body_pose(mount, q).actInv(world.body_pose(tool, q))
        motion = np.zeros(model.nv)
        for joint, value in zip(group.joints, positions):     # one dof per joint
            index = model.joints[model.getJointId(joint)].idx_v
            motion[index] = value
        pin.framesForwardKinematics(model, data, pin.integrate(model, pin.neutral(model),
                                                                motion))
        theirs = (data.oMf[model.getFrameId(mount)].actInv(data.oMf[model.getFrameId(tool)]))
        np.testing.assert_allclose(ours.homogeneous, theirs.homogeneous, atol=1e-9)


@pytest.mark.parametrize("name", list(ARMS))
def test_reaches_as_often_as_pink(name):
    """Twenty seeded targets from nearby starts: at least Pink's success count, no joint
    past its limits, finite commands."""
    pytest.importorskip("pink")
    world, group, tool = arm(name)
    cases = problems(world, group, tool, TARGETS, seed=sum(map(ord, name)))
    ours = [run_ours(world, group, tool, case) for case in cases]
    pink = [run_pink(world, group, tool, case) for case in cases]
    ours_reached = sum(o.reached for o in ours)
    pink_reached = sum(o.reached for o in pink)
    assert ours_reached >= pink_reached, (name, ours_reached, pink_reached)
    assert ours_reached >= TARGETS - 2, (name, ours_reached)
    assert sum(o.violations for o in ours) == 0
    assert all(o.finite for o in ours)
