"""The gaze task on BAZAR's pan-tilt unit: Jacobian, convergence, moving targets, and
its place in the language (targets, units, measures)."""

import textwrap

import numpy as np
import pytest

from robocop_dsl.compile import check_source
from robocop_dsl.control import CURRENT, BodyTarget, Controller, InvalidParameter, UnknownName

CAMERA = "kinect2_rgb_optical_frame"
LEFT_TOOL = "bazar_left_hankamp_tool_object_side"


@pytest.fixture
def world(bazar):
    """A private copy of BAZAR (tests attach bodies)."""
    return bazar.copy()


def head(world, time_step=0.02, **task):
    controller = Controller(world, "bazar_ptu", time_step)
    controller.add_constraint("joint_kinematic", "limits", "bazar_ptu", max_velocity=1.0)
    gaze = controller.add_task("gaze", "watch", CAMERA, **{"target": "part_body", **task})
    gaze.enable()
    return controller, gaze


def follow(controller, q, cycles):
    """Run ``cycles`` control cycles integrating the command; returns the final q."""
    q = q.copy()
    for _ in range(cycles):
        result = controller.compute(q)
        assert result.solved, result.reason
        q[controller.state.q_indices] += result.velocity * controller.time_step
    controller.update_state(q)
    return q


@pytest.mark.parametrize("axis", ["x", "y", "z"])
def test_jacobian_matches_finite_differences(world, axis):
    """The 2 x 2 Jacobian on the pan and tilt joints is the derivative of the value."""
    controller, gaze = head(world, axis=axis)
    q = world.initial_configuration()
    q[controller.state.q_indices] = [0.3, -0.2]
    controller.update_state(q)
    jacobian = gaze.compute_jacobian(controller.state)
    value = gaze.compute_value(controller.state)
    numeric = np.zeros((2, 2))
    for column, index in enumerate(controller.state.q_indices):
        moved = q.copy()
        moved[index] += 1e-7
        controller.update_state(moved)
        numeric[:, column] = (gaze.compute_value(controller.state) - value) / 1e-7
    assert np.allclose(jacobian, numeric, atol=1e-5)


def test_the_camera_turns_to_the_part(world):
    """From about 30 degrees off, the optical axis points at the part within 0.05 degree
    after 2 s at 20 ms."""
    controller, gaze = head(world, gain=4)
    q = world.initial_configuration()
    controller.update_state(q)
    assert np.degrees(gaze.error) > 20
    q = follow(controller, q, 100)
    assert np.degrees(gaze.error) < 0.05
    camera = world.body_pose(CAMERA, q)
    towards = world.body_pose("part_body", q).translation - camera.translation
    assert camera.rotation[:, 2] @ towards / np.linalg.norm(towards) > np.cos(1e-3)


def test_a_point_target(world):
    """A point [m] in the world is watched too."""
    controller, gaze = head(world, target=[1.0, -0.3, 0.8], gain=4)
    q = follow(controller, world.initial_configuration(), 150)
    camera = world.body_pose(CAMERA, q)
    towards = np.array([1.0, -0.3, 0.8]) - camera.translation
    assert camera.rotation[:, 2] @ towards / np.linalg.norm(towards) > np.cos(np.radians(0.1))
    assert gaze.error == pytest.approx(gaze.angle)


def test_the_head_follows_a_part_carried_by_the_arm(world):
    """With the part attached to the left tool, moving the arm moves the watched point;
    the head lags by less than 3 degrees while it moves and catches up once it stops."""
    controller, gaze = head(world, gain=5)
    q = follow(controller, world.initial_configuration(), 100)
    kinematics = controller.kinematics
    kinematics.attach("part_body", LEFT_TOOL)
    arm = world.joint_group("bazar_left_arm").q_indices
    worst = 0.0
    for _ in range(150):
        q[arm] += np.array([0.3, 0.2, 0, 0.2, 0, 0, 0]) * 0.02
        q = follow(controller, q, 1)
        worst = max(worst, np.degrees(gaze.error))
    before = world.body_pose("part_body", world.initial_configuration()).translation
    assert np.linalg.norm(kinematics.body_pose("part_body").translation - before) > 0.1
    assert worst < 3.0
    follow(controller, q, 50)
    assert np.degrees(gaze.error) < 0.05


def test_nothing_watched_asks_for_no_motion(world):
    """A gaze with the target ``current`` (or none) has a zero Jacobian and error."""
    controller, gaze = head(world, target=CURRENT)
    result = controller.compute(world.initial_configuration())
    assert result.solved and np.allclose(result.velocity, 0)
    assert gaze.error == 0.0 and gaze.target is None


def test_bad_axis_and_unknown_body_are_refused(world):
    """The axis is x, y or z; the watched body must exist."""
    with pytest.raises(InvalidParameter, match="axis"):
        head(world, axis="w")
    _, gaze = head(world)
    with pytest.raises(UnknownName, match="part_bdy"):
        gaze.target = BodyTarget("part_bdy")


def test_offset_target_in_the_reference_frame(world):
    """``BODY offset`` shifts the watched point [m] in the task's reference frame."""
    controller, _ = head(world, target=BodyTarget("part_body", np.array([0, 0, 0.3])), gain=4)
    q = follow(controller, world.initial_configuration(), 150)
    point = world.body_pose("part_body", q).translation + [0, 0, 0.3]
    camera = world.body_pose(CAMERA, q)
    towards = (point - camera.translation) / np.linalg.norm(point - camera.translation)
    assert camera.rotation[:, 2] @ towards > np.cos(np.radians(0.1))


MISSION = """\
    mission look
    world "bazar/sophia.yaml"
    task watch: gaze(kinect2_rgb_optical_frame) {{
        target = {target}
        interpolator = otg(max_velocity = 1 rad/s, max_acceleration = 2 rad/s^2)
    }}
    state looking {{
        enter {{ enable watch }}
        when {condition} -> done
    }}
    final done
"""


def diagnostics(target="part_body", condition="watch.error < 1 deg"):
    text = textwrap.dedent(MISSION.format(target=target, condition=condition))
    return [(d.code, d.message) for d in check_source(text, "look.mission").diagnostics]


@pytest.mark.parametrize("target", ["part_body", "part_body offset [0, 0, 10] cm",
                                    "[1, 0, 0.8] m", "current"])
def test_gaze_targets_the_language_accepts(target):
    """A body, an offset body, a point in metres or ``current``; otg limits in rad/s."""
    assert diagnostics(target) == []


@pytest.mark.parametrize("target, code", [
    ("[1, 0, 0] rad", "wrong-dimension"),
    ("[1, 0] m", "wrong-length"),
    ("pose(position = [1, 0, 0] m)", "wrong-target"),
    ("part_bodi", "unknown-body"),
])
def test_gaze_targets_the_language_refuses(target, code):
    """An angle, a short vector, a pose or an unknown body is not a gaze target."""
    assert [c for c, _ in diagnostics(target)] == [code]


def test_gaze_error_is_an_angle():
    """``watch.error`` compares with angles, not lengths; it has no position_error."""
    assert diagnostics(condition="watch.error < 2 mm")[0][0] == "wrong-dimension"
    assert diagnostics(condition="watch.position_error < 1 deg")[0][0] == "unknown-field"
