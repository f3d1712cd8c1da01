"""The run log: events as JSON lines, the time series as Parquet, plots with state bands."""

import numpy as np
import pytest

from robocop_dsl.cli.main import main
from robocop_dsl.runtime.log import RunLogger, read_events, read_timeseries
from robocop_dsl.runtime.plot import legend_columns, state_spans
from robocop_dsl.runtime.records import CycleRecord, Event, TaskView


def synthetic_run(folder, cycles=50):
    logger = RunLogger(folder, ["j1", "j2"])
    logger.on_event(Event("start", 0.0, 0, {"state": "a"}))
    for cycle in range(cycles):
        state = "a" if cycle < 20 else "b"
        if cycle == 20:
            logger.on_event(Event("transition", 0.2, 20, {"from": "a", "to": "b",
                                                          "condition": "elapsed > 0.2 s"}))
        view = TaskView("arm", "joint", None, 1.0 / (cycle + 1), np.zeros(2),
                        np.array([cycle, -cycle], float))
        logger.on_cycle(CycleRecord(cycle, cycle * 0.01, state, np.zeros(2),
                                    np.array([cycle, 2 * cycle], float), np.ones(2), True,
                                    (view,), {}, 1e-4, 2e-4))
    logger.on_stop(None)


def test_time_series_columns(tmp_path):
    synthetic_run(tmp_path)
    data = read_timeseries(tmp_path)
    assert list(data) == ["cycle", "time", "state", "solved", "q.j1", "q.j2", "command.j1",
                          "command.j2", "error.arm", "reference.arm.0", "reference.arm.1",
                          "cycle_time", "compute_time"]
    np.testing.assert_allclose(data["q.j2"], 2 * np.arange(50))
    assert list(data["state"][:21]) == ["a"] * 20 + ["b"]
    np.testing.assert_allclose(data["error.arm"][-1], 1 / 50)
    np.testing.assert_allclose(data["reference.arm.1"][5], -5)


def test_pandas_reads_it(tmp_path):
    pandas = pytest.importorskip("pandas")
    synthetic_run(tmp_path)
    frame = pandas.read_parquet(tmp_path / "timeseries.parquet")
    assert frame.shape == (50, 13)


def test_events_are_json_lines(tmp_path):
    synthetic_run(tmp_path)
    events = read_events(tmp_path)
    assert [e["kind"] for e in events] == ["start", "transition"]
    assert events[1] == {"kind": "transition", "time": 0.2, "cycle": 20, "from": "a",
                         "to": "b", "condition": "elapsed > 0.2 s"}


def test_state_spans():
    time = np.arange(6) * 0.5
    assert state_spans(time, np.array(["a", "a", "b", "b", "b", "c"])) == [
        ("a", 0.0, 1.0), ("b", 1.0, 2.5), ("c", 2.5, 2.5)]


def test_plot_command_writes_pngs(tmp_path, capsys):
    synthetic_run(tmp_path / "log")
    assert main(["plot", str(tmp_path / "log"), "-o", str(tmp_path / "png")]) == 0
    written = capsys.readouterr().out.split()
    assert [p.rsplit("/", 1)[1] for p in written] == [
        "joint_positions.png", "velocity_commands.png", "task_errors.png"]
    for path in written:
        assert open(path, "rb").read(8) == b"\x89PNG\r\n\x1a\n"


def test_plot_command_without_a_log(tmp_path, capsys):
    assert main(["plot", str(tmp_path)]) == 1
    assert "no timeseries.parquet here" in capsys.readouterr().err


def test_long_configurations_get_fewer_legend_columns():
    """Configurations of three regions fit across the figure two to a row; short state
    names eight to a row."""
    long = ["both/left/above | both/right/above | both/head/look"] * 10
    assert legend_columns(long) == 2
    assert legend_columns([f"state_{i}" for i in range(12)]) == 8
    assert legend_columns(["only"]) == 1


def test_pose_errors_are_logged_in_metres_and_radians(tmp_path):
    """Each error field says its unit; a pose task's error also comes as its position
    [m] and orientation [rad] parts, whose root sum of squares is the logged norm."""
    import pyarrow.parquet as pq

    from conftest import MISSIONS
    from robocop_dsl.runtime import load_mission

    runner = load_mission(MISSIONS / "pickup.mission").runner()
    runner.add_observer(RunLogger(tmp_path, runner.joint_names))
    runner.run(duration=3.0)
    units = {f.name: f.metadata[b"unit"].decode()
             for f in pq.read_schema(tmp_path / "timeseries.parquet") if f.metadata}
    assert units["error.arms"] == "rad" and units["error.watch"] == "rad"
    assert units["error.left_tool"] == "m+rad"
    assert (units["error.left_tool.position"], units["error.left_tool.orientation"]) == (
        "m", "rad")
    data = read_timeseries(tmp_path)
    logged = ~np.isnan(data["error.left_tool"])
    assert logged.sum() > 10
    np.testing.assert_allclose(np.hypot(data["error.left_tool.position"][logged],
                                        data["error.left_tool.orientation"][logged]),
                               data["error.left_tool"][logged], rtol=1e-9)
