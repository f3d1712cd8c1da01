"""The ROS 2 messages of a run: definitions as ROS 2 Humble's, bytes as
mcap-ros2-support encodes them, poses as pinocchio computes them, an MCAP file that
rosbags reads at every checkpoint."""

import shutil
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

from robocop_dsl.ecosystem.cdr import encoder
from robocop_dsl.ecosystem.description import robot_description
from robocop_dsl.ecosystem.frames import BodyFrames, position_quaternion
from robocop_dsl.ecosystem.mcap_file import McapFile
from robocop_dsl.ecosystem.msgdefs import message_definition
from robocop_dsl.ecosystem.topics import RunTopics, Topic
from robocop_dsl.runtime import load_mission
from robocop_dsl.runtime.records import Observer
from robocop_dsl.world import load_world

TYPES = ["std_msgs/msg/String", "sensor_msgs/msg/JointState", "tf2_msgs/msg/TFMessage",
         "visualization_msgs/msg/MarkerArray", "geometry_msgs/msg/WrenchStamped",
         "rcl_interfaces/msg/Log"]


@pytest.mark.parametrize("name", TYPES)
def test_message_definitions_are_ros2_humble_s(name):
    text, _ = get_typestore(Stores.ROS2_HUMBLE).generate_msgdef(name, ros_version=2)
    assert message_definition(name) == text


def fields(message):
    """A message read by rosbags as the dictionary mcap-ros2-support encodes."""
    if hasattr(message, "__dataclass_fields__"):
        return {name: fields(getattr(message, name)) for name in message.__dataclass_fields__
                if name != "__msgtype__"}
    if isinstance(message, list):
        return [fields(item) for item in message]
    return message.tolist() if isinstance(message, np.ndarray) else message


class Keep(Observer):
    def __init__(self):
        self.records = []

    def on_cycle(self, record):
        self.records.append(record)


def run_messages(mission: str, world: str, duration: float) -> tuple:
    """The topics of ``duration`` [s] of ``mission`` on ``world`` and their messages."""
    mission = load_mission(mission, world=load_world(world))
    runner = mission.runner()
    topics = RunTopics(mission.world, runner.joint_names, 0.02)
    keep = Keep()
    runner.add_observer(keep)
    runner.run(duration=duration)
    out = topics.opening()
    for first in range(0, len(keep.records), 200):
        out += topics.cycles(keep.records[first:first + 200])
    return topics, out


@pytest.fixture(scope="module")
def messages():
    """7 s of the pickup on the physics world: the part a free body, lifted by the
    left tool from 6.3 s."""
    return run_messages("missions/pickup.mission", "bazar/sophia_physics.yaml", 7.0)


@pytest.fixture(scope="module")
def pressing():
    """2 s of the Panda pressing the table: a force sensor at its wrist."""
    return run_messages("missions/panda_press.mission", "panda/panda_press.yaml", 2.0)


@pytest.mark.parametrize("run", ["messages", "pressing"])
def test_every_message_is_encoded_as_mcap_ros2_support_does(run, request):
    """rosbags reads each message; mcap-ros2-support encodes what it read into the
    same bytes."""
    topics, out = request.getfixturevalue(run)
    typestore = get_typestore(Stores.ROS2_HUMBLE)
    types = {topic.name: topic.type for topic in topics.topics}
    seen = set()
    for topic, _, data in out:
        if topic in seen and topic not in ("/mission/targets",):
            continue
        seen.add(topic)
        message = typestore.deserialize_cdr(data, types[topic])
        assert encoder(types[topic])(fields(message)) == data, topic
    assert {"/joint_states", "/tf", "/tf_static", "/mission/targets",
            "/robot_description", "/mission/state"} <= seen
    assert seen >= {topic.name for topic in topics.topics} - {"/mission/events", "/rosout"}


def test_free_bodies_are_on_tf_where_physics_put_them(messages):
    topics, out = messages
    typestore = get_typestore(Stores.ROS2_HUMBLE)
    tf = [typestore.deserialize_cdr(data, "tf2_msgs/msg/TFMessage")
          for topic, _, data in out if topic == "/tf"]
    parts = [t for message in tf for t in message.transforms if t.child_frame_id == "part_body"]
    assert len(parts) == len(tf)
    heights = [t.transform.translation.z for t in parts]
    assert heights[0] == pytest.approx(0.78, abs=0.03)          # on the workbench
    assert heights[-1] > heights[0] + 0.03                      # lifted


@pytest.mark.parametrize("name", ["bazar/sophia_physics.yaml", "panda/panda_pick.yaml",
                                  "kinova/jaco.yaml"])
def test_body_poses_are_pinocchio_s(name):
    """Revolute, continuous, prismatic, mimic and floating joints."""
    world = load_world(name)
    frames = BodyFrames(world)
    model = world.model.copy()
    model.lowerPositionLimit = np.where(np.isfinite(model.lowerPositionLimit),
                                        model.lowerPositionLimit, -3)
    model.upperPositionLimit = np.where(np.isfinite(model.upperPositionLimit),
                                        model.upperPositionLimit, 3)
    configurations = np.array([pin.randomConfiguration(model) for _ in range(5)])
    poses = frames.moving_poses(configurations)
    for q, row in zip(configurations, poses):
        placements = world.body_placements(q)
        for body, pose in zip(frames.moving, row):
            np.testing.assert_allclose(pose, placements[body].homogeneous, atol=1e-12)
    for body, pose in zip(frames.fixed, frames.fixed_poses):
        np.testing.assert_allclose(pose, placements[body].homogeneous, atol=1e-12)


def test_quaternions_are_pinocchio_s_with_w_positive():
    poses = [pin.SE3.Random() for _ in range(100)]
    poses += [pin.SE3(pin.exp3(np.pi * np.array(axis) / np.linalg.norm(axis)), np.ones(3))
              for axis in [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, -1, 0), (1, 2, -3)]]
    ours = position_quaternion(np.array([pose.homogeneous for pose in poses]))
    for pose, mine in zip(poses, ours):
        theirs = pin.SE3ToXYZQUAT(pose)
        theirs[3:] *= np.sign(theirs[6]) or 1.0
        np.testing.assert_allclose(mine, theirs, atol=1e-12)


def test_meshes_are_file_uris_pinocchio_loads(panda):
    description = robot_description(panda)
    model = pin.buildModelFromXML(description)
    assert list(model.names) == list(panda.model.names)
    assert "file:///" in description
    uri = description.split('filename="file://')[1].split('"')[0]
    assert uri.endswith((".stl", ".dae", ".obj", ".STL")) and Path(uri).is_file()


def test_the_file_is_readable_at_every_checkpoint(tmp_path):
    """After each checkpoint, a copy of the file as it is (the run killed then) holds
    every message so far; the closed file has its summary."""
    topics = [Topic("/mission/state", "std_msgs/msg/String", True)]
    string = encoder("std_msgs/msg/String")
    mcap = McapFile(tmp_path / "run.mcap", topics)
    for second in range(3):
        mcap.write([("/mission/state", (second * 100 + i) * 10**7, string({"data": str(i)}))
                    for i in range(100)])
        mcap.checkpoint()
        shutil.copy(tmp_path / "run.mcap", tmp_path / "killed.mcap")
        with AnyReader([tmp_path / "killed.mcap"],
                       default_typestore=get_typestore(Stores.EMPTY)) as reader:
            assert len(list(reader.messages())) == 100 * (second + 1)
    mcap.close()
    from mcap.reader import make_reader

    with open(tmp_path / "run.mcap", "rb") as file:
        summary = make_reader(file).get_summary()
    assert summary.statistics.message_count == 300
