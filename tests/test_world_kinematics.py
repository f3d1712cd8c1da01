"""Forward kinematics of the BAZAR arm against poses computed by hand.

Left arm mount: x 0.05, y 0.22, z 0.9 (base 0.35 + torso 0.5 + mount 0.05). Joint 2 is
0.31 m above the mount, joint 4 0.4 m further, joint 6 0.39 m further, the flange 0.078 m
after joint 6; the tool adapter adds 0.03 m and the Hankamp tool 0.14 m.
"""

import numpy as np
import pytest

MOUNT = np.array([0.05, 0.22, 0.9])
FLANGE = 0.31 + 0.4 + 0.39 + 0.078


def posture(bazar, **joints):
    q = bazar.neutral_configuration()
    for index, value in joints.items():
        joint = bazar.model.joints[bazar.model.getJointId(f"bazar_left_joint_{index[1:]}")]
        q[joint.idx_q] = value
    return q


def test_zero_posture_is_straight_up(bazar):
    q = posture(bazar)
    flange = bazar.body_pose("bazar_left_link_7", q)
    np.testing.assert_allclose(flange.translation, MOUNT + [0, 0, FLANGE], atol=1e-12)
    np.testing.assert_allclose(flange.rotation, np.eye(3), atol=1e-12)
    tool = bazar.body_pose("bazar_left_hankamp_tool_object_side", q)
    np.testing.assert_allclose(tool.translation, MOUNT + [0, 0, FLANGE + 0.17], atol=1e-12)


def test_shoulder_at_right_angle_points_forward(bazar):
    """Joint 2 (axis +y) at +90 deg turns the arm from +z to +x about the shoulder."""
    q = posture(bazar, j2=np.pi / 2)
    flange = bazar.body_pose("bazar_left_link_7", q)
    np.testing.assert_allclose(flange.translation, MOUNT + [FLANGE - 0.31, 0, 0.31], atol=1e-12)
    np.testing.assert_allclose(flange.rotation[:, 2], [1, 0, 0], atol=1e-12)


def test_base_rotation_then_shoulder(bazar):
    q = posture(bazar, j1=np.pi / 2, j2=np.pi / 2)
    flange = bazar.body_pose("bazar_left_link_7", q)
    np.testing.assert_allclose(flange.translation, MOUNT + [0, FLANGE - 0.31, 0.31], atol=1e-12)


def test_elbow_bends_backwards_for_positive_angles(bazar):
    """Joint 4's axis is -y: +90 deg folds the forearm towards -x at the elbow."""
    q = posture(bazar, j4=np.pi / 2)
    flange = bazar.body_pose("bazar_left_link_7", q)
    elbow_height = 0.31 + 0.4
    np.testing.assert_allclose(flange.translation,
                               MOUNT + [-(FLANGE - elbow_height), 0, elbow_height], atol=1e-12)


@pytest.mark.parametrize("angle", [0.3, -1.1])
def test_last_joint_spins_the_tool_about_its_axis(bazar, angle):
    q = posture(bazar, j7=angle)
    tool = bazar.body_pose("bazar_left_hankamp_tool_object_side", q)
    np.testing.assert_allclose(tool.translation, MOUNT + [0, 0, FLANGE + 0.17], atol=1e-12)
    np.testing.assert_allclose(tool.rotation[:, 0], [np.cos(angle), np.sin(angle), 0], atol=1e-12)


def test_jacobian_matches_finite_differences(bazar):
    rng = np.random.default_rng(3)
    q = bazar.initial_configuration() + rng.uniform(-0.3, 0.3, bazar.model.nq)
    body = "bazar_left_hankamp_tool_object_side"
    jacobian = bazar.body_jacobian(body, q)
    step = 1e-7
    for column in range(bazar.model.nv):
        dq = np.zeros(bazar.model.nv)
        dq[column] = step
        moved = bazar.body_pose(body, q + dq).translation
        np.testing.assert_allclose((moved - bazar.body_pose(body, q).translation) / step,
                                   jacobian[:3, column], atol=1e-5)
