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


def test_a_task_whose_reference_overflows_brakes_within_the_acceleration_limit(tmp_path):
    """A gain so large that the pose task's reference velocity is not finite: the cycle
    is refused (``qp_failure``) and the run brakes from the command it had sent, within
    the mission's 5 rad/s^2, instead of commanding zero at once. Recomputed from the
    Parquet log with pyarrow, through the command line."""
    import json
    import subprocess
    import sys
    from pathlib import Path

    import pyarrow.parquet as pq

    repo = Path(__file__).resolve().parent.parent
    pickup = (repo / "missions" / "pickup.mission").read_text()
    mission = tmp_path / "overflow.mission"
    mission.write_text(pickup.replace('world "bazar/sophia.yaml"',
                                      f'world "{repo}/robots/bazar/sophia.yaml"')
                       .replace("proportional(gain = 5)", "proportional(gain = 1e300)"))
    done = subprocess.run([sys.executable, "-m", "robocop_dsl", "run", str(mission),
                           "--log", str(tmp_path / "log")], capture_output=True, text=True)
    assert done.returncode == 1 and "Traceback" not in done.stderr
    events = [json.loads(line) for line in (tmp_path / "log" / "events.jsonl").open()]
    failures = [event for event in events if event["kind"] == "qp_failure"]
    assert len(failures) == 1
    table = pq.read_table(tmp_path / "log" / "timeseries.parquet")
    columns = [name for name in table.column_names if name.startswith("command.")]
    commands = np.column_stack([table[name].to_numpy() for name in columns])
    steps = np.diff(table["time"].to_numpy())
    moving = np.abs(commands[failures[0]["cycle"] - 1]).max()
    assert moving > 0.05            # the arm moved when the cycle was refused
    accelerations = np.abs(np.diff(commands, axis=0)) / steps[:, None]
    assert accelerations.max() <= 5.0 * (1 + 1e-6) + TOLERANCE
    assert "every promise held" in done.stdout
