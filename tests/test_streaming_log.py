"""The run log is streamed: row groups of one second of mission time written while the
run goes, so a killed run keeps all of them but the one in progress, and a finished
run has them joined in ``timeseries.parquet``."""

import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq

from conftest import write
from robocop_dsl.runtime import load_mission, read_events, read_timeseries
from robocop_dsl.runtime.log import PARTS, TIMESERIES, RunLogger

REPO = Path(__file__).resolve().parent.parent

LONG = """
mission long
world "bazar/sophia.yaml"

task arms: joint_position(bazar_arms) {
    interpolator = otg(max_velocity = 0.2 rad/s, max_acceleration = 1 rad/s^2)
}
task left_tool: body_position(bazar_left_hankamp_tool_object_side) {
    reference = world
}

state sway {
    enter { enable arms
            arms.target = [0.5, 0.5, 0, -1.5, 0, 0.7, 0, 0, 0.25, 0, -2, 0, 0.7, 0] rad }
    when elapsed > 600 s -> done
}
final done
"""


def test_a_killed_run_keeps_every_finished_row_group(tmp_path):
    path = write(tmp_path, "long.mission", LONG)
    log = tmp_path / "log"
    process = subprocess.Popen([sys.executable, "-m", "robocop_dsl", "run", str(path),
                                "--log", str(log)], cwd=REPO, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
    parts = log / PARTS
    while not (parts.is_dir() and len(list(parts.glob("*.parquet"))) >= 3):
        assert process.poll() is None, "the run ended before writing three row groups"
        time.sleep(0.02)
    process.send_signal(signal.SIGKILL)
    process.wait()
    assert not (log / TIMESERIES).exists()
    data = read_timeseries(log)
    rows = len(data["cycle"])
    assert rows >= 3 * 200 and rows % 200 == 0          # whole seconds at 5 ms
    np.testing.assert_array_equal(data["cycle"], np.arange(rows))
    np.testing.assert_allclose(data["time"], np.arange(rows) * 0.005)
    assert np.isfinite(data["q.bazar_left_joint_1"]).all()
    assert np.isnan(data["error.left_tool"]).all()      # never enabled: a column of NaN
    assert np.isfinite(data["error.arms"]).all()
    assert read_events(log)[0]["kind"] == "start"


def logged_run(tmp_path, seconds: float):
    """The long mission run for ``seconds`` of mission time with a :class:`RunLogger`
    in ``tmp_path / "log"``; checks it succeeded and left no row group files."""
    mission = load_mission(write(tmp_path, "long.mission",
                                 LONG.replace("elapsed > 600 s", f"elapsed > {seconds} s")))
    runner = mission.runner()
    runner.add_observer(RunLogger(tmp_path / "log", runner.joint_names))
    result = runner.run()
    assert result.outcome == "success"
    assert not (tmp_path / "log" / PARTS).exists()
    return result


def test_a_finished_run_joins_its_row_groups(tmp_path):
    result = logged_run(tmp_path, 2.5)
    metadata = pq.ParquetFile(tmp_path / "log" / TIMESERIES).metadata
    assert metadata.num_rows == result.cycles and metadata.num_row_groups == 1
    data = read_timeseries(tmp_path / "log")
    np.testing.assert_array_equal(data["cycle"], np.arange(result.cycles))
    assert set(data["state"]) == {"sway", "done"}
    assert list(data).index("error.arms") < list(data).index("error.left_tool")


def test_row_groups_are_joined_while_the_run_goes(tmp_path, monkeypatch):
    """Every :data:`JOINED_GROUPS` row groups become one row group of the joined file
    as the run goes (here 2 of 1 s each, so a 5.5 s run gives row groups of 2, 2 and
    the last 1.5 s), and the file holds every cycle once, in order."""
    monkeypatch.setattr("robocop_dsl.runtime.log.JOINED_GROUPS", 2)
    result = logged_run(tmp_path, 5.5)
    assert sorted(path.name for path in (tmp_path / "log").iterdir()) == [
        "events.jsonl", TIMESERIES]
    metadata = pq.ParquetFile(tmp_path / "log" / TIMESERIES).metadata
    sizes = [metadata.row_group(index).num_rows for index in range(metadata.num_row_groups)]
    assert sizes[:2] == [400, 400] and sum(sizes) == result.cycles
    data = read_timeseries(tmp_path / "log")
    np.testing.assert_array_equal(data["cycle"], np.arange(result.cycles))
    assert np.isfinite(data["error.arms"]).all()
