"""``run --log`` writes ``run.mcap`` beside the time series: ROS 2 messages that rosbags
(a reader the project does not write) reads back: one ``/joint_states`` per cycle equal
to the Parquet's, the tool and the part on ``/tf`` where pinocchio puts them, a URDF on
``/robot_description`` that pinocchio loads with the world's joints, the state changes
of ``events.jsonl`` on ``/mission/state``."""

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

from conftest import MISSIONS
from robocop_dsl.cli.main import main
from robocop_dsl.runtime import read_events, read_timeseries

TOOL, PART = "bazar_left_hankamp_tool_object_side", "part_body"


def read_mcap(path: Path) -> dict:
    """Topic -> [(log time [ns], message)], every message of the file, with rosbags."""
    messages: dict = {}
    with AnyReader([path], default_typestore=get_typestore(Stores.EMPTY)) as reader:
        for connection, time, raw in reader.messages():
            messages.setdefault(connection.topic, []).append(
                (time, reader.deserialize(raw, connection.msgtype)))
    return messages


def transform(message, child: str):
    """``(parent, 4x4)`` of ``child`` in a ``TFMessage``, or ``None``."""
    for stamped in message.transforms:
        if stamped.child_frame_id == child:
            t, r = stamped.transform.translation, stamped.transform.rotation
            pose = pin.XYZQUATToSE3(np.array([t.x, t.y, t.z, r.x, r.y, r.z, r.w]))
            return stamped.header.frame_id, pose.homogeneous
    return None


@pytest.fixture(scope="module")
def logged(tmp_path_factory):
    """The pickup, run headless with ``--log``: the folder and the MCAP's messages."""
    folder = tmp_path_factory.mktemp("pickup") / "log"
    assert main(["run", str(MISSIONS / "pickup.mission"), "--log", str(folder)]) == 0
    return folder, read_mcap(folder / "run.mcap")


def test_one_joint_state_per_cycle_as_in_the_parquet(logged):
    folder, messages = logged
    data = read_timeseries(folder)
    joints = [name[2:] for name in data if name.startswith("q.")]
    states = messages["/joint_states"]
    assert len(states) == len(data["cycle"])
    assert [time for time, _ in states] == [round(t * 1e9) for t in data["time"]]
    assert all(list(message.name) == joints for _, message in states)
    positions = np.array([message.position for _, message in states])
    np.testing.assert_array_equal(positions, np.column_stack([data[f"q.{j}"] for j in joints]))
    velocities = np.array([message.velocity for _, message in states])
    np.testing.assert_array_equal(velocities,
                                  np.column_stack([data[f"command.{j}"] for j in joints]))
    stamp = states[7][1].header.stamp
    assert stamp.sec * 10**9 + stamp.nanosec == states[7][0]


def test_every_joint_of_the_world_is_on_joint_states(tmp_path):
    """The Panda's run drives its arm only: its fingers are on ``/joint_states`` too, the
    second mimicking the first, as pinocchio reads them from ``/robot_description``."""
    folder = tmp_path / "log"
    assert main(["run", str(MISSIONS / "panda_reach.mission"), "--log", str(folder),
                 "--duration", "0.2"]) == 1
    data = read_timeseries(folder)
    states = read_mcap(folder / "run.mcap")
    description = states["/robot_description"][0][1].data
    model = pin.buildModelFromXML(description)
    moving = {model.names[i] for i in range(1, model.njoints) if model.joints[i].nv}
    controlled = [name[2:] for name in data if name.startswith("q.")]
    for _, message in states["/joint_states"]:
        assert list(message.name[:len(controlled)]) == controlled
        assert set(message.name) == moving
    last = states["/joint_states"][-1][1]
    position = dict(zip(last.name, last.position))
    velocity = dict(zip(last.name, last.velocity))
    assert [position[j] for j in controlled] == [data[f"q.{j}"][-1] for j in controlled]
    assert [velocity[j] for j in controlled] == [data[f"command.{j}"][-1] for j in controlled]
    assert position["panda_finger_joint1"] == position["panda_finger_joint2"] == 0.0
    assert np.isnan(velocity["panda_finger_joint1"]) and np.isnan(velocity["panda_finger_joint2"])


def test_the_tool_and_the_part_are_on_tf_where_the_model_puts_them(logged, bazar):
    """Every 20 ms, from the world frame; the part from its grasp on, carried by the
    tool (the same relative pose at every message), before it only on /tf_static."""
    folder, messages = logged
    data = read_timeseries(folder)
    group = bazar.joint_group("bazar_upper_joints")
    tf = messages["/tf"]
    assert len(tf) == pytest.approx(len(data["cycle"]) / 4, abs=2)
    for time, message in tf[::40]:
        row = int(np.argmin(np.abs(data["time"] - time * 1e-9)))
        q = bazar.initial_configuration()
        q[group.q_indices] = group.space.coordinates(
            np.array([data[f"q.{j}"][row] for j in group.joints]))
        parent, pose = transform(message, TOOL)
        assert parent == "world"
        np.testing.assert_allclose(pose, bazar.body_pose(TOOL, q).homogeneous, atol=1e-9)
    grasp = next(e for e in read_events(folder) if e.get("action") == "attach")
    carried = [(time, transform(m, TOOL)[1], transform(m, PART)) for time, m in tf
               if transform(m, PART) is not None]
    held = [np.linalg.inv(tool) @ part[1] for time, tool, part in carried
            if grasp["time"] * 1e9 <= time <= 9.1e9]
    assert len(held) > 100
    np.testing.assert_allclose(held[-1], held[0], atol=1e-9)
    [(_, static)] = messages["/tf_static"]
    assert transform(static, PART)[0] == "world"
    assert transform(static, TOOL) is None


def test_the_robot_description_loads_back_into_pinocchio(logged, bazar):
    _, messages = logged
    [(time, description)] = messages["/robot_description"]
    model = pin.buildModelFromXML(description.data)
    assert time == 0
    assert list(model.names) == list(bazar.model.names)
    assert model.nq == bazar.model.nq


def test_the_state_changes_are_those_of_the_events(logged):
    """A message at the start and at every cycle whose transitions changed the active
    configuration, which it gives (as the time series' state column)."""
    folder, messages = logged
    data = read_timeseries(folder)
    changes = [(time, message.data) for time, message in messages["/mission/state"]]
    transitions = sorted({round(e["time"] * 1e9) for e in read_events(folder)
                          if e["kind"] == "transition"})
    assert [time for time, _ in changes] == [0] + transitions
    for time, state in changes:
        assert data["state"][int(np.argmin(np.abs(data["time"] - time * 1e-9)))] == state
    assert changes[-1][1] == "done"


def test_every_event_is_on_mission_events_and_rosout(logged):
    folder, messages = logged
    lines = (folder / "events.jsonl").read_text().splitlines()
    assert [message.data for _, message in messages["/mission/events"]] == lines
    logs = [message for _, message in messages["/rosout"]]
    assert len(logs) == len(lines)
    assert any(log.msg.startswith("transition goto_initial_pose -> approach") for log in logs)
    assert logs[-1].msg.startswith("end: success")


def test_the_targets_are_markers_in_the_world(logged):
    """While a pose task is enabled, its target and its reference as three arrows each,
    after a DELETEALL; the last message clears them."""
    _, messages = logged
    targets = messages["/mission/targets"]
    assert len(targets) > 50
    markers = [message.markers for _, message in targets]
    assert all(m[0].action == 3 for m in markers)
    tool = [m for m in markers if any(marker.ns == "left_tool/target" for marker in m)]
    assert tool and all(len([x for x in m if x.ns.startswith("left_tool/")]) == 6 for m in tool)
    assert all(marker.header.frame_id == "world" for m in markers for marker in m[1:])


def test_a_log_that_cannot_start_says_why(tmp_path):
    """The writing process's error comes back to the run's process before the run."""
    from robocop_dsl.ecosystem.log_process import LogProcess, LogProcessError
    from robocop_dsl.runtime.run_info import RunInfo

    info = RunInfo(0.005, ["j"], {}, [], [], {}, {}, str(tmp_path / "nowhere.yaml"))
    log = LogProcess(tmp_path / "log")
    with pytest.raises(LogProcessError, match="did not start: .*cannot find world file"):
        log.prepare(info, "batch")
    log.close()


def test_tasks_that_cannot_reach_the_writing_process_are_an_error_not_a_traceback(tmp_path):
    """The writing process computes the task views with copies of the run's tasks: a
    task that cannot be copied there stops the log before the run, with the reason."""
    from robocop_dsl.ecosystem.log_process import LogProcess, LogProcessError
    from robocop_dsl.runtime import load_mission

    runner = load_mission(MISSIONS / "pickup.mission").runner()
    runner.tasks()[0].note = lambda: None         # a lambda cannot be pickled
    log = LogProcess(tmp_path / "log")
    with pytest.raises(LogProcessError, match="tasks cannot be sent to the log's writing"):
        log.prepare(runner, "batch")
    assert log._process.poll() is not None


def test_the_log_is_whole_when_the_run_returns_and_its_process_then_ends_by_itself(tmp_path):
    """The run waits for the writing process's reply that the files are closed, not for
    its exit: when ``run`` returns, the time series and ``run.mcap`` hold every cycle,
    and the process then ends on its own, with code 0."""
    from robocop_dsl.ecosystem.log_process import LogProcess
    from robocop_dsl.runtime import load_mission

    runner = load_mission(MISSIONS / "pickup.mission").runner()
    log = LogProcess(tmp_path / "log")
    runner.observers.append(log)
    result = runner.run(duration=1.0)
    log.close()                         # as the command does once the run returned
    data = read_timeseries(tmp_path / "log")
    np.testing.assert_array_equal(data["cycle"], np.arange(result.cycles))
    assert len(read_mcap(tmp_path / "log" / "run.mcap")["/joint_states"]) == result.cycles
    assert log._process.wait() == 0
