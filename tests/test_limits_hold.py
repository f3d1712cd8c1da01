"""Limits that always hold: missions generated with random joint limits above and below
the URDF's, random targets near and past reach and random gains run with the log on
BAZAR and the Panda; every logged command stays within the URDF's and the mission's
velocity limits and the mission's acceleration limit, stops included, and is finite."""

import numpy as np
import pytest

from robocop_dsl.runtime import RunLogger, load_mission, read_timeseries
from robocop_dsl.world import load_world

from mission_generator import MissionGenerator, Scene

WORLDS = ("bazar/sophia.yaml", "panda/panda_on_table.yaml")
SEEDS = range(100, 110)
DURATION = 2.0
"""Mission time of each run before it is stopped [s]."""
TOLERANCE = 1e-6
"""Slack on a limit [rad/s, rad/s^2]: the QP's own tolerance is far below."""


@pytest.fixture(scope="module", params=WORLDS)
def scene(request):
    return Scene(load_world(request.param), request.param)


@pytest.mark.parametrize("seed", SEEDS)
def test_logged_commands_keep_every_limit(scene, seed, tmp_path):
    path = tmp_path / "generated.mission"
    path.write_text(MissionGenerator(scene, seed).mission())
    runner = load_mission(path).runner()
    runner.add_observer(RunLogger(tmp_path / "log", runner.joint_names))
    result = runner.run(duration=DURATION)
    limits = runner.controller.constraint("c_joint_kinematic")
    group = scene.group
    data = read_timeseries(tmp_path / "log")
    commands = np.array([data[f"command.{joint}"] for joint in runner.joint_names]).T
    assert len(commands) == result.cycles and np.isfinite(commands).all()
    speed = np.minimum(group.max_velocity, limits.max_velocity)
    assert np.all(np.abs(commands) <= speed + TOLERANCE)
    rest = np.zeros((1, len(runner.joint_names)))
    accelerations = np.abs(np.diff(np.vstack([rest, commands, rest]), axis=0)) / runner.time_step
    assert np.all(accelerations <= limits.max_acceleration * (1 + 1e-6) + TOLERANCE)
