"""Recorded replays, decoded: the scene comes before the animation, every body and every
enabled task's target is there, one frame per viewer period, poses as in the run."""

import numpy as np
import pinocchio as pin
import pytest

from robocop_dsl.runtime import read_timeseries
from robocop_dsl.viewer import ReplayRecorder, ViewerError, read_replay, viewer_options
from robocop_dsl.viewer.geometry import WorldGeometry, body_path
from robocop_dsl.viewer.labels import label_path
from viewer_runs import STATES, pickup_run, synthetic_run

PERIOD = 0.04


def record_run(world, records, path):
    recorder = ReplayRecorder(world, path, viewer_options(world), title="pickup <replay>")
    recorder.on_start(None)
    for item in records:
        recorder.on_cycle(item)
    recorder.on_stop(None)
    assert recorder.problems == []
    return recorder


def tracks_by_path(commands):
    """Animated path -> {property: [(frame, value), ...]} and the clips' frame rates."""
    (animation,) = [c for c in commands if c["type"] == "set_animation"]
    tracks, rates = {}, set()
    for clip in animation["animations"]:
        rates.add(clip["clip"]["fps"])
        tracks[clip["path"]] = {t["name"]: [(k["time"], k["value"]) for k in t["keys"]]
                                for t in clip["clip"]["tracks"]}
    return tracks, rates


def static_pose(commands, path):
    """The last plain transform sent to ``path`` (its pose when not animated)."""
    matrices = [c["matrix"] for c in commands if c["type"] == "set_transform"
                and c["path"] == path]
    return np.array(matrices[-1]).reshape(4, 4).T


def animated_pose(tracks, frame):
    """The 4x4 pose of a node at an animation frame, from its position and quaternion."""
    position = dict(tracks[".position"])[frame]
    x, y, z, w = dict(tracks[".quaternion"])[frame]
    pose = np.eye(4)
    pose[:3, :3] = pin.Quaternion(w, x, y, z).toRotationMatrix()
    pose[:3, 3] = position
    return pose


@pytest.fixture(scope="module")
def synthetic(bazar, tmp_path_factory):
    """A recorded synthetic run: its records, recorder and decoded commands."""
    records = synthetic_run(bazar)
    path = tmp_path_factory.mktemp("replay") / "synthetic.html"
    recorder = record_run(bazar, records, path)
    return records, recorder, read_replay(path)


def test_scene_commands_come_before_the_animation(synthetic):
    """All shapes and placements are sent first; the single animation comes last."""
    _, _, commands = synthetic
    types = [c["type"] for c in commands]
    assert types[-1] == "set_animation" and types.count("set_animation") == 1
    assert max(i for i, t in enumerate(types) if t == "set_object") < len(types) - 1


def test_every_body_and_enabled_target_is_in_the_replay(bazar, synthetic):
    """Robot links, workbench, part, camera, both tasks' markers and every state label."""
    _, _, commands = synthetic
    objects = {c["path"] for c in commands if c["type"] == "set_object"}
    geometry = WorldGeometry(bazar)
    for body in geometry.body_names():
        for path in geometry.paths_of(body):
            assert f"/meshcat/{path}" in objects, body
    for body in ("workbench", "part_body", "kinect2_link", "bazar_left_link_1"):
        assert geometry.paths_of(body)
    for task in ("left_tool", "right_point"):
        for which in ("target", "reference"):
            assert any(p.startswith(f"/meshcat/targets/{task}/{which}") for p in objects)
    assert not any("/targets/arms" in p for p in objects)
    assert {f"/meshcat/states/{name}" for name, _ in STATES} <= objects


def test_one_animation_frame_per_viewer_period(synthetic):
    """2 s of run at 40 ms per frame: 51 frames, every track keyed at each of them."""
    records, recorder, commands = synthetic
    duration = records[-1].time - records[0].time
    frames = int(round(duration / PERIOD)) + 1
    assert len(recorder.frame_records) == frames == 51
    for index, item in enumerate(recorder.frame_records):
        assert item.time == pytest.approx(index * PERIOD)
    tracks, rates = tracks_by_path(commands)
    assert len(rates) == 1 and rates.pop() == pytest.approx(1 / PERIOD)
    for path, properties in tracks.items():
        for keys in properties.values():
            assert [frame for frame, _ in keys] == list(range(frames)), path


def moved_bodies(records, until):
    """Last reported pose of each body attached at some cycle up to ``until``."""
    moved = {}
    for item in records:
        if item.cycle > until.cycle:
            break
        moved.update(item.body_poses)
    return moved


def drawn_pose(commands, tracks, path, frame):
    """A node's pose at an animation frame: from its tracks, or its one transform."""
    key = f"/meshcat/{path}"
    return animated_pose(tracks[key], frame) if key in tracks else static_pose(commands, key)


def test_robot_poses_match_the_run(bazar, synthetic):
    """Each frame's body poses are those of the configuration recorded at that time."""
    records, recorder, commands = synthetic
    tracks, _ = tracks_by_path(commands)
    geometry = WorldGeometry(bazar)
    for frame, item in enumerate(recorder.frame_records):
        expected = geometry.poses(item.q, moved_bodies(records, item))
        for path, pose in expected.items():
            np.testing.assert_allclose(drawn_pose(commands, tracks, path, frame), pose,
                                       atol=1e-9, err_msg=path)
    assert f"/meshcat/{body_path('bazar_left_link_7')}" in tracks
    assert f"/meshcat/{body_path('workbench')}" not in tracks
    for path, offset in geometry.offsets().items():
        np.testing.assert_allclose(static_pose(commands, f"/meshcat/{path}"), offset)


def test_attached_part_moves_with_the_tool(bazar, synthetic):
    """After the attach, the part's cube follows the pose reported for it."""
    _, recorder, commands = synthetic
    tracks, _ = tracks_by_path(commands)
    part = tracks[f"/meshcat/{body_path('part_body')}"]
    lifted = [i for i, item in enumerate(recorder.frame_records) if item.state == "lift"]
    assert len(lifted) > 5
    for frame in lifted:
        pose = recorder.frame_records[frame].body_poses["part_body"]
        np.testing.assert_allclose(animated_pose(part, frame), pose, atol=1e-9)
    assert not np.allclose(animated_pose(part, lifted[0]), animated_pose(part, lifted[-1]))


def test_detached_part_stays_where_it_was_left(bazar, synthetic):
    """Once no longer attached, the part keeps the last pose reported for it."""
    records, recorder, commands = synthetic
    tracks, _ = tracks_by_path(commands)
    part = tracks[f"/meshcat/{body_path('part_body')}"]
    released = [i for i, item in enumerate(recorder.frame_records) if item.state == "release"]
    last_attached = [item for item in records if item.body_poses][-1].body_poses["part_body"]
    assert len(released) > 3
    for frame in released:
        np.testing.assert_allclose(animated_pose(part, frame), last_attached, atol=1e-9)


def test_targets_show_only_while_enabled_and_labels_follow_the_state(synthetic):
    """Visibility tracks: a task's markers show in the states that enable it, and the
    label of the active state is the only one shown."""
    _, recorder, commands = synthetic
    tracks, _ = tracks_by_path(commands)
    states = [item.state for item in recorder.frame_records]
    left = dict(tracks["/meshcat/targets/left_tool/target"][".visible"])
    right = dict(tracks["/meshcat/targets/right_point/reference"][".visible"])
    for frame, state in enumerate(states):
        assert left[frame] == (state in ("approach", "grasp"))
        assert right[frame] == (state in ("grasp", "lift", "release"))
        shown = [name for name, _ in STATES
                 if dict(tracks[f"/meshcat/states/{name}"][".visible"])[frame]]
        assert shown == [state]


def test_target_poses_follow_the_records(synthetic):
    """Target and ghost markers are where the records put them."""
    _, recorder, commands = synthetic
    tracks, _ = tracks_by_path(commands)
    for frame, item in enumerate(recorder.frame_records):
        for task in item.tasks:
            if task.name == "left_tool":
                np.testing.assert_allclose(
                    animated_pose(tracks["/meshcat/targets/left_tool/target"], frame),
                    task.target, atol=1e-9)
                np.testing.assert_allclose(
                    animated_pose(tracks["/meshcat/targets/left_tool/reference"], frame),
                    task.reference, atol=1e-9)


def test_replay_is_standalone(synthetic):
    """The page embeds meshcat's client and loads nothing from elsewhere."""
    _, recorder, _ = synthetic
    text = recorder.path.read_text(encoding="utf-8")
    assert "MeshCat.Viewer" in text and "<title>pickup &lt;replay&gt;</title>" in text
    assert "<script src" not in text and "<link" not in text


def test_recorder_reports_a_file_it_cannot_write(bazar, tmp_path):
    """A replay that cannot be written is reported, not raised into the run."""
    blocker = tmp_path / "file"
    blocker.write_text("")
    recorder = ReplayRecorder(bazar, blocker / "replay.html")
    for item in synthetic_run(bazar, duration=0.1):
        recorder.on_cycle(item)
    recorder.on_stop(None)
    assert len(recorder.problems) == 1 and "could not write the replay" in recorder.problems[0]


def test_reading_a_page_that_is_not_a_replay(tmp_path):
    """read_replay names the file it cannot decode."""
    page = tmp_path / "page.html"
    page.write_text("<html></html>")
    with pytest.raises(ViewerError, match="not a replay file"):
        read_replay(page)


@pytest.fixture(scope="module")
def pickup(tmp_path_factory):
    """The pickup mission run once with a recorder and a log: result, recorder, decoded
    replay and logged time series."""
    folder = tmp_path_factory.mktemp("pickup")
    result, (recorder,) = pickup_run(
        lambda world: [ReplayRecorder(world, folder / "pickup.html", viewer_options(world))],
        folder / "log")
    assert result.outcome == "success" and recorder.problems == []
    return result, recorder, read_replay(recorder.path), read_timeseries(folder / "log")


def logged_configuration(world, log, row):
    """The world's configuration at a row of the logged time series."""
    q = world.initial_configuration()
    for column, values in log.items():
        if column.startswith("q."):
            joint = world.model.joints[world.model.getJointId(column[2:])]
            q[joint.idx_q] = values[row]
    return q


def frame_rows(log, frames):
    """The log row shown by each frame: the latest at or before the frame's time."""
    times = log["time"]
    return [int(np.searchsorted(times, times[0] + i * PERIOD + 1e-9, side="right")) - 1
            for i in range(frames)]


def test_pickup_replay_has_every_body_and_enabled_target(bazar, pickup):
    """The recorded pickup holds the robot, workbench, part, camera, the markers of the
    Cartesian task it enabled, and a label for every state its frames show (a state of
    one cycle may fall between two frames), which cover every top-level state."""
    _, recorder, commands, log = pickup
    objects = {c["path"] for c in commands if c["type"] == "set_object"}
    geometry = WorldGeometry(bazar)
    for body in geometry.body_names():
        for path in geometry.paths_of(body):
            assert f"/meshcat/{path}" in objects, body
    kinds = {t.name: t.kind for item in recorder.frame_records for t in item.tasks}
    assert set(kinds) == {c[len("error."):] for c in log
                          if c.startswith("error.") and c.count(".") == 1}
    assert kinds["left_tool"] == "pose" and kinds["arms"] == "joint"
    for task, kind in kinds.items():
        drawn = {p for p in objects if p.startswith(f"/meshcat/targets/{task}/")}
        if kind in ("pose", "orientation"):
            assert {f"/meshcat/targets/{task}/{w}/{axis}" for w in ("target", "reference")
                    for axis in "xyz"} == drawn
        elif kind in ("position", "gaze"):
            assert {f"/meshcat/targets/{task}/target",
                    f"/meshcat/targets/{task}/reference"} == drawn
        else:
            assert not drawn
    shown = {item.state for item in recorder.frame_records}
    assert {s.split("/")[0] for s in shown} == {s.split("/")[0] for s in set(log["state"])}
    assert {f"/meshcat/{label_path(s)}" for s in shown} <= objects


def test_pickup_replay_has_one_frame_per_viewer_period(pickup):
    """Frames cover the run at 40 ms each, the last one showing the final cycle; every
    track has a key at every frame."""
    _, recorder, commands, log = pickup
    frames = int(np.ceil((log["time"][-1] - log["time"][0]) / PERIOD - 1e-9)) + 1
    assert len(recorder.frame_records) == frames
    assert recorder.frame_records[-1].state == log["state"][-1] == "done"
    tracks, rates = tracks_by_path(commands)
    assert len(rates) == 1 and rates.pop() == pytest.approx(1 / PERIOD)
    for path, properties in tracks.items():
        for keys in properties.values():
            assert [frame for frame, _ in keys] == list(range(frames)), path


def test_pickup_replay_robot_poses_match_the_log(bazar, pickup):
    """At every frame each robot link is where the logged joint positions put it."""
    _, recorder, commands, log = pickup
    tracks, _ = tracks_by_path(commands)
    robot = [b for b in WorldGeometry(bazar).body_names() if b.startswith("bazar_")]
    rows = frame_rows(log, len(recorder.frame_records))
    for frame, row in enumerate(rows):
        q = logged_configuration(bazar, log, row)
        for body in robot:
            np.testing.assert_allclose(drawn_pose(commands, tracks, body_path(body), frame),
                                       bazar.body_pose(body, q).homogeneous, atol=1e-9,
                                       err_msg=body)


def test_pickup_replay_targets_and_labels_follow_the_log(pickup):
    """The tool's target shows exactly while the log has its error; the label shown is
    the logged state."""
    _, recorder, commands, log = pickup
    tracks, _ = tracks_by_path(commands)
    target = dict(tracks["/meshcat/targets/left_tool/target"][".visible"])
    labels = {path: dict(properties[".visible"])
              for path, properties in tracks.items() if path.startswith("/meshcat/states/")}
    for frame, row in enumerate(frame_rows(log, len(recorder.frame_records))):
        assert target[frame] == (not np.isnan(log["error.left_tool"][row]))
        assert [path for path, shown in labels.items() if shown[frame]] == \
            [f"/meshcat/{label_path(log['state'][row])}"]


def test_pickup_part_is_carried_and_left_at_the_drop(bazar, pickup):
    """The part leaves the workbench with the tool and stays where it was released."""
    _, recorder, commands, _ = pickup
    tracks, _ = tracks_by_path(commands)
    part = tracks[f"/meshcat/{body_path('part_body')}"]
    first, last = animated_pose(part, 0), animated_pose(part, len(recorder.frame_records) - 1)
    drop = bazar.body_pose("drop_point", bazar.initial_configuration()).translation
    np.testing.assert_allclose(first[:3, 3], [0.7, 0.2, 0.76], atol=1e-9)
    np.testing.assert_allclose(last[:3, 3], drop, atol=2e-3)
