"""The viewer's scene on the real BAZAR world: options, geometry poses, targets, labels
and the camera's starting view."""

from types import SimpleNamespace

import meshcat
import numpy as np
import pinocchio as pin
import pytest
import umsgpack
from meshcat.commands import SetTransform
from meshcat.path import Path

from robocop_dsl.runtime.records import CycleRecord, TaskView
from robocop_dsl.viewer import Scene, ViewerError, ViewerOptions, viewer_options
from robocop_dsl.viewer.commands import CommandLog, pack_transform
from robocop_dsl.viewer.geometry import WorldGeometry, body_path
from robocop_dsl.world import Processor

LEFT_TOOL = "bazar_left_hankamp_tool_object_side"


def expected_geometry_pose(world, geometry, q):
    """A geometry's world pose computed the long way: its body's pose, then its offset."""
    frame = world.model.frames[geometry.parentFrame]
    body = world.body_pose(frame.name, q)
    return (body * frame.placement.inverse() * geometry.placement).homogeneous


def record(world, q, state="approach", tasks=(), body_poses=None):
    return CycleRecord(cycle=0, time=0.0, state=state, q=q, positions=q, command=q * 0,
                       solved=True, tasks=tuple(tasks), body_poses=body_poses or {})


def loaded_scene(world, *records):
    """A scene loaded into a command log, with the markers and labels of ``records``."""
    log = CommandLog()
    visualizer = meshcat.Visualizer(window=log)
    scene = Scene(world)
    scene.load(visualizer)
    for item in records:
        scene.load_new(visualizer, item)
    return scene, log


def test_options_come_from_the_meshcat_processor(bazar):
    """The world's `viewer: {type: meshcat, options: {period: 40ms}}` gives 0.04 s."""
    assert viewer_options(bazar) == ViewerOptions(period=0.04)


def test_options_default_without_a_viewer_processor():
    """A world without a meshcat processor gets the default period."""
    world = SimpleNamespace(processors={"driver": Processor("driver", "simulated", {})})
    assert viewer_options(world).period == pytest.approx(0.04)


@pytest.mark.parametrize("period", [0, -0.1, "fast", float("inf")])
def test_bad_period_is_an_error(period):
    """A period that is not a positive duration is refused, naming the value."""
    world = SimpleNamespace(processors={"viewer": Processor("viewer", "meshcat",
                                                            {"period": period})})
    with pytest.raises(ViewerError, match="positive duration"):
        viewer_options(world)


def test_geometry_follows_the_configuration(bazar):
    """Every body node is at its body's pose, and every geometry object lands where the
    world model puts it, for a configuration that moves the arms."""
    geometry = WorldGeometry(bazar)
    q = bazar.initial_configuration()
    q[bazar.joint_group("bazar_arms").q_indices] += 0.3
    poses = geometry.poses(q)
    offsets = geometry.offsets()
    assert set(poses) == {body_path(b) for b in geometry.body_names()}
    for body in geometry.body_names():
        np.testing.assert_allclose(poses[body_path(body)],
                                   bazar.body_pose(body, q).homogeneous, atol=1e-12)
    for item in bazar.visual_model.geometryObjects:
        body = bazar.model.frames[item.parentFrame].name
        drawn = poses[body_path(body)] @ offsets[f"{body_path(body)}/{item.name}"]
        np.testing.assert_allclose(drawn, expected_geometry_pose(bazar, item, q), atol=1e-12)


def test_attached_body_follows_its_reported_pose(bazar):
    """The part is drawn where the run says the attached part is."""
    geometry = WorldGeometry(bazar)
    part = np.eye(4)
    part[:3, 3] = [0.5, 0.1, 1.2]
    poses = geometry.poses(bazar.initial_configuration(), {"part_body": part})
    np.testing.assert_allclose(poses[body_path("part_body")], part, atol=1e-12)


def test_scene_has_robot_and_environment_bodies(bazar):
    """Loading sends a shape for every body with visual geometry: robot links, workbench,
    part and camera."""
    scene, log = loaded_scene(bazar)
    objects = {c["path"] for c in log.commands if c["type"] == "set_object"}
    bodies = scene.geometry.body_names()
    assert {"workbench", "part_body", "kinect2_link", "bazar_left_link_7",
            "bazar_right_hankamp_tool_robot_side"} <= set(bodies)
    for body in bodies:
        for path in scene.geometry.paths_of(body):
            assert f"/meshcat/{path}" in objects


def test_camera_frames_robot_workbench_and_label(bazar):
    """Every corner of every body, and the state label, is in the camera's 75 degree
    view of a 4:3 page, and the view is not much wider than needed."""
    scene = Scene(bazar)
    centre, position = scene.camera
    points = np.vstack([scene.geometry.corners(bazar.initial_configuration()),
                        scene.label_position])
    forward = (centre - position) / np.linalg.norm(centre - position)
    right = np.cross(forward, [0, 0, 1])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    depth = (points - position) @ forward
    vertical = np.abs((points - position) @ up) / depth
    horizontal = np.abs((points - position) @ right) / depth
    half_height = np.tan(np.radians(75) / 2)
    assert np.all(depth > 0)
    assert np.all(vertical <= half_height) and np.all(horizontal <= half_height * 4 / 3)
    assert max(vertical.max() / half_height, horizontal.max() / half_height / (4 / 3)) > 0.8


def test_camera_commands_centre_the_view(bazar):
    """The camera is set with plain commands: the scene is shifted by -centre and the
    camera placed relative to the centre, in meshcat's y-up camera frame."""
    scene, log = loaded_scene(bazar)
    centre, position = scene.camera
    shifts = {c["path"]: np.array(c["matrix"]).reshape(4, 4).T for c in log.commands
              if c["type"] == "set_transform" and c["path"] in ("/meshcat", "/Grid", "/Axes")}
    assert set(shifts) == {"/meshcat", "/Grid", "/Axes"}
    for shift in shifts.values():
        np.testing.assert_allclose(shift[:3, 3], -centre)
    (camera,) = [c for c in log.commands if c["type"] == "set_property"
                 and c["path"] == "/Cameras/default/rotated/<object>"]
    x, y, z = position - centre
    np.testing.assert_allclose(camera["value"], [x, z, -y])


def test_pose_target_and_reference_markers(bazar):
    """A pose task shows a triad at its target and a smaller ghost at its reference."""
    q = bazar.initial_configuration()
    target = bazar.body_pose("pickup_point", q).homogeneous
    reference = bazar.body_pose(LEFT_TOOL, q).homogeneous
    task = TaskView("left_tool", "pose", LEFT_TOOL, 0.1, target, reference)
    item = record(bazar, q, tasks=[task])
    scene, log = loaded_scene(bazar, item)
    frame = scene.frame(item)
    np.testing.assert_allclose(frame.poses["targets/left_tool/target"], target)
    np.testing.assert_allclose(frame.poses["targets/left_tool/reference"], reference)
    assert frame.visible["targets/left_tool/target"] is True
    axes = [c for c in log.commands if c["type"] == "set_object"
            and c["path"].startswith("/meshcat/targets/left_tool/")]
    heights = {c["path"]: c["object"]["geometries"][0]["height"] for c in axes}
    assert len(axes) == 6
    assert heights["/meshcat/targets/left_tool/reference/x"] < \
        heights["/meshcat/targets/left_tool/target/x"]


def test_position_target_is_a_sphere_and_joint_tasks_have_no_marker(bazar):
    """A position task shows spheres; a joint task has nothing to show in space."""
    q = bazar.initial_configuration()
    tasks = [TaskView("reach", "position", LEFT_TOOL, 0.1, np.array([0.5, 0.2, 1.0]),
                      np.array([0.4, 0.2, 1.1])),
             TaskView("arms", "joint", None, 0.1, np.zeros(14), np.zeros(14))]
    item = record(bazar, q, tasks=tasks)
    scene, log = loaded_scene(bazar, item)
    spheres = [c for c in log.commands if c["type"] == "set_object"
               and c["path"].startswith("/meshcat/targets/reach/")]
    assert {c["object"]["geometries"][0]["type"] for c in spheres} == {"SphereGeometry"}
    assert scene.frame(item).poses["targets/reach/target"][:3, 3].tolist() == [0.5, 0.2, 1.0]
    assert not any("/targets/arms" in c["path"] for c in log.commands)


def test_orientation_target_is_drawn_at_its_body(bazar):
    """An orientation target has no position of its own: its triad sits on the body."""
    q = bazar.initial_configuration()
    rotation = np.eye(4)
    rotation[:3, :3] = pin.rpy.rpyToMatrix(np.pi, 0, 0)
    task = TaskView("tool_down", "orientation", LEFT_TOOL, 0.1, rotation, rotation)
    item = record(bazar, q, tasks=[task])
    scene, _ = loaded_scene(bazar, item)
    pose = scene.frame(item).poses["targets/tool_down/target"]
    np.testing.assert_allclose(pose[:3, 3], bazar.body_pose(LEFT_TOOL, q).translation)
    np.testing.assert_allclose(pose[:3, :3], rotation[:3, :3])


def test_disabled_task_markers_and_inactive_labels_are_hidden(bazar):
    """Once a task is no longer in the records its markers hide; only the active
    state's label shows."""
    q = bazar.initial_configuration()
    task = TaskView("reach", "position", LEFT_TOOL, 0.1, np.ones(3), np.ones(3))
    first = record(bazar, q, state="approach", tasks=[task])
    second = record(bazar, q, state="grasp")
    scene, log = loaded_scene(bazar, first, second)
    visible = scene.frame(second).visible
    assert visible == {"targets/reach/target": False, "targets/reach/reference": False,
                       "states/approach": False, "states/grasp": True}
    labels = [c for c in log.commands if c["type"] == "set_object"
              and c["path"].startswith("/meshcat/states/")]
    assert [c["object"]["object"]["type"] for c in labels] == ["Sprite", "Sprite"]
    assert [c["object"]["textures"][0]["text"] for c in labels] == ["approach", "grasp"]


def test_gaze_target_is_a_sphere_at_the_watched_point(bazar):
    """A gaze task shows where its body looks; its reference (two sines) has no place."""
    q = bazar.initial_configuration()
    watched = bazar.body_pose("part_body", q).homogeneous
    task = TaskView("watch", "gaze", "kinect2_rgb_optical_frame", 0.2, watched, np.zeros(2))
    item = record(bazar, q, tasks=[task])
    scene, _ = loaded_scene(bazar, item)
    frame = scene.frame(item)
    np.testing.assert_allclose(frame.poses["targets/watch/target"][:3, 3], watched[:3, 3])
    assert frame.visible["targets/watch/target"] is True
    assert frame.visible["targets/watch/reference"] is False


def test_fast_transform_packing_matches_meshcat():
    """The publisher's packed transforms are byte for byte meshcat's own."""
    matrix = np.arange(16.0).reshape(4, 4) / 7
    for path in ("/meshcat/a", "/meshcat/world/visuals/bazar_right_hankamp_tool_robot_side",
                 "/meshcat/" + "long" * 80):
        expected = umsgpack.packb(SetTransform(matrix, Path(tuple(path[1:].split("/")))).lower())
        assert pack_transform(path, matrix) == expected
