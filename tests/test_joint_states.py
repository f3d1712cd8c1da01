"""What ``/joint_states`` gives for every joint of a world: a continuous joint's angle,
a mimic joint's position and velocity from the joint it follows (here continuous, with a
multiplier and an offset), whether that joint is commanded or not."""

import math

import numpy as np
import pytest

from robocop_dsl.ecosystem.joint_states import JointStates
from robocop_dsl.runtime.records import CycleRecord
from robocop_dsl.world import load_world

URDF = """<robot name="wheel">
  <link name="base"/><link name="wheel"/><link name="marker"/>
  <joint name="spin" type="continuous">
    <parent link="base"/><child link="wheel"/><axis xyz="0 0 1"/>
    <limit velocity="1" effort="1"/>
  </joint>
  <joint name="follow" type="continuous">
    <parent link="wheel"/><child link="marker"/><axis xyz="0 0 1"/>
    <limit velocity="1" effort="1"/>
    <mimic joint="spin" multiplier="2" offset="0.1"/>
  </joint>
</robot>
"""


@pytest.fixture(scope="module")
def world(tmp_path_factory):
    folder = tmp_path_factory.mktemp("wheel")
    (folder / "wheel.urdf").write_text(URDF)
    (folder / "w.yaml").write_text("models:\n  - path: wheel.urdf\n")
    return load_world(folder / "w.yaml")


def record(world, angle: float, command: list) -> CycleRecord:
    q = world.initial_configuration()
    q[:2] = [math.cos(angle), math.sin(angle)]
    return CycleRecord(0, 0.0, "s", q, np.array([angle])[:len(command)], np.array(command),
                       True, (), {})


@pytest.mark.parametrize("controlled, command, velocities", [
    ([], [], [math.nan, math.nan]),
    (["spin"], [0.5], [0.5, 1.0]),
])
def test_a_mimic_of_a_continuous_joint(world, controlled, command, velocities):
    states = JointStates(world, controlled)
    assert states.names == ["spin", "follow"]
    values = states.values([record(world, 2.5, command)])[0]
    np.testing.assert_allclose(values[:2], [2.5, 2 * 2.5 + 0.1])
    np.testing.assert_allclose(values[2:], velocities)
