"""Task views are captured in the cycle and computed when read: they hold the state of
their own cycle, in the world frame, whatever the controller did since."""

import numpy as np
import pinocchio as pin
import pytest

from robocop_dsl.control import CURRENT, BodyTarget, Controller, OTGInterpolator
from robocop_dsl.runtime import load_mission
from robocop_dsl.runtime.records import Observer
from robocop_dsl.runtime.views import task_views

from conftest import MISSIONS

LEFT_TOOL = "bazar_left_hankamp_tool_object_side"
RIGHT_TOOL = "bazar_right_hankamp_tool_object_side"
CAMERA = "kinect2_rgb_optical_frame"


@pytest.fixture()
def moving(bazar):
    """A controller whose tasks cover every kind, several in a moving reference frame
    (the right tool, which ``arms`` moves), and the state where it starts."""
    controller = Controller(bazar, "bazar_upper_joints", 0.005)
    controller.add_constraint("joint_kinematic", "limits", "bazar_upper_joints")
    q = bazar.initial_configuration()
    q[bazar.joint_group("bazar_arms").q_indices] = [0, 0.4, 0, -1.2, 0, 0.8, 0] * 2
    goal = pin.SE3(pin.rpy.rpyToMatrix(0.1, -0.2, 0.3), np.array([0.1, 0.3, 0.05]))
    tasks = [
        controller.add_task("body_pose", "pose", LEFT_TOOL, reference=RIGHT_TOOL,
                            target=goal, interpolator=OTGInterpolator(0.2, 0.5), weight=0.1),
        controller.add_task("body_position", "position", LEFT_TOOL, reference=RIGHT_TOOL,
                            target=[0.0, 0.4, 0.0], weight=0.1),
        controller.add_task("body_orientation", "orientation", LEFT_TOOL,
                            reference=RIGHT_TOOL, target=CURRENT, weight=0.1),
        controller.add_task("joint_position", "arms", "bazar_right_arm",
                            target=[0.3, 0.2, 0, -1.5, 0, 0.6, 0],
                            interpolator=OTGInterpolator(1.0, 1.0)),
        controller.add_task("gaze", "watch", CAMERA, target=BodyTarget("part_body")),
        controller.add_task("body_velocity", "push", RIGHT_TOOL, target=[0.01, 0, 0, 0, 0, 0],
                            weight=0.01),
    ]
    for task in tasks:
        task.enable()
    return controller, q


def expected_views(world, controller, q, held_rotation, velocity):
    """Each task's (error, world target, world reference), computed from the world's own
    forward kinematics at ``q`` rather than from the controller's."""
    def pose(body):
        return world.body_pose(body, q)

    frame = pose(RIGHT_TOOL)
    tool = frame.actInv(pose(LEFT_TOOL))
    tasks = {task.name: task for task in controller.tasks()}
    goal = tasks["pose"].target
    arms_indices = world.joint_group("bazar_right_arm").q_indices
    camera = pose(CAMERA)
    direction = camera.rotation.T @ (pose("part_body").translation - camera.translation)
    push = tasks["push"]
    return {
        "pose": (np.linalg.norm(pin.log6(tool.actInv(goal)).vector), (frame * goal).homogeneous,
                 (frame * tasks["pose"].reference_value).homogeneous),
        "position": (np.linalg.norm(tasks["position"].target - tool.translation),
                     frame.act(tasks["position"].target),
                     frame.act(tasks["position"].reference_value)),
        "orientation": (np.linalg.norm(pin.log3(tool.rotation.T @ held_rotation)),
                        _at(frame.rotation @ held_rotation, pose(LEFT_TOOL).translation),
                        _at(frame.rotation @ held_rotation, pose(LEFT_TOOL).translation)),
        "arms": (np.linalg.norm(tasks["arms"].target - q[arms_indices]), tasks["arms"].target,
                 tasks["arms"].reference_value.copy()),
        "watch": (np.arccos(direction[2] / np.linalg.norm(direction)),
                  pose("part_body").homogeneous, tasks["watch"].reference_value.copy()),
        "push": (np.linalg.norm(push.target - controller.state.jacobian(push.body_id) @ velocity),
                 push.target, push.target),
    }


def _at(rotation, translation):
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = rotation, translation
    return pose


def test_views_keep_their_cycle_in_the_world_frame(bazar, moving):
    """Views read 50 cycles after their own give that cycle's errors, targets and
    references, equal to the world's forward kinematics at the cycle's state."""
    controller, q = moving
    held = bazar.body_pose(RIGHT_TOOL, q).actInv(bazar.body_pose(LEFT_TOOL, q)).rotation
    kept = []
    for cycle in range(60):
        velocity = controller.state.velocity.copy()
        result = controller.compute(q)
        assert result.solved, result.reason
        if cycle in (1, 20, 40):
            kept.append((task_views(controller),
                         expected_views(bazar, controller, q, held, velocity)))
        q = q.copy()
        q[controller.state.q_indices] += result.velocity * controller.time_step
        controller.update_state(q)
    for views, expected in kept:
        assert [view.name for view in views] == list(expected)
        for view in views:
            error, target, reference = expected[view.name]
            assert view.error == pytest.approx(error, abs=1e-9), view.name
            np.testing.assert_allclose(view.target, target, atol=1e-9, err_msg=view.name)
            np.testing.assert_allclose(view.reference, reference, atol=1e-9,
                                       err_msg=view.name)
    assert kept[0][0][0].error != pytest.approx(kept[-1][0][0].error, abs=1e-6)


def test_views_hold_the_enabled_tasks_only(moving):
    """A disabled task has no view; the kinds are those the viewer and log draw."""
    controller, q = moving
    controller.tasks()[1].disable()
    controller.compute(q)
    views = task_views(controller)
    assert [(v.name, v.kind) for v in views] == [
        ("pose", "pose"), ("orientation", "orientation"), ("arms", "joint"),
        ("watch", "gaze"), ("push", "velocity")]
    assert len(views) == 5 and views[2].name == "arms"


def test_error_follows_a_new_target_in_the_same_state(moving):
    """The error the controller computed is reused in its state, but a target set
    afterwards is seen at once."""
    controller, q = moving
    controller.compute(q)
    position = controller.tasks()[1]
    before = position.error
    assert position.sample().goal is position.target
    position.target = position.target + np.array([0.0, 0.0, 0.1])
    assert position.error == pytest.approx(np.hypot(before, 0.1), rel=0.2)
    assert position.error != pytest.approx(before, abs=1e-3)
    np.testing.assert_allclose(position.sample().goal, position.target)


class Keeper(Observer):
    """Keeps every record; at some cycles, the tasks' errors computed in the cycle."""

    def __init__(self, runner):
        self.runner = runner
        self.records = []
        self.errors = {}

    def on_cycle(self, record):
        self.records.append(record)
        if record.cycle % 50 == 0:
            self.errors[record.cycle] = {task.name: task.error
                                         for task in self.runner.controller.tasks()
                                         if task.enabled}


def test_a_whole_mission_read_afterwards_matches_its_cycles():
    """Over pickup (attach and detach included), the views of every 50th cycle, read
    after the run, give the errors the tasks had in that cycle."""
    runner = load_mission(MISSIONS / "pickup.mission").runner()
    keeper = Keeper(runner)
    runner.add_observer(keeper)
    assert runner.run().outcome == "success"
    assert len(keeper.errors) > 40
    for cycle, errors in keeper.errors.items():
        views = {view.name: view.error for view in keeper.records[cycle].tasks}
        assert views == pytest.approx(errors, abs=1e-12), cycle
