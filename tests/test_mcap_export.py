"""``robocop-mission export LOG --mcap``: a log folder as the ``run.mcap`` the run would
have written (the same joint states, bodies and states), the world from the log's
``start`` event or, for older logs that do not name it, from ``--world``."""

import json

import numpy as np
import pytest

from conftest import MISSIONS
from robocop_dsl.cli.main import main
from test_mcap_log import PART, TOOL, read_mcap, transform


@pytest.fixture(scope="module")
def logged(tmp_path_factory):
    """The pickup, 7 s of it with ``--log``, and its folder exported to another file."""
    folder = tmp_path_factory.mktemp("export") / "log"
    assert main(["run", str(MISSIONS / "pickup.mission"), "--log", str(folder),
                 "--duration", "7"]) == 1
    assert main(["export", str(folder), "--mcap", "-o", str(folder / "exported.mcap")]) == 0
    return folder, read_mcap(folder / "run.mcap"), read_mcap(folder / "exported.mcap")


def test_the_export_has_the_run_s_joint_states_bodies_and_states(logged):
    _, written, exported = logged
    for topic in ("/joint_states", "/mission/state", "/mission/events"):
        assert [time for time, _ in exported[topic]] == [time for time, _ in written[topic]]
    np.testing.assert_array_equal([m.position for _, m in exported["/joint_states"]],
                                  [m.position for _, m in written["/joint_states"]])
    assert ([m.data for _, m in exported["/mission/state"]]
            == [m.data for _, m in written["/mission/state"]])
    assert [t for t, _ in exported["/tf"]] == [t for t, _ in written["/tf"]]
    for (_, mine), (_, theirs) in zip(exported["/tf"], written["/tf"]):
        for body in (TOOL, PART):
            ours = transform(mine, body)
            if transform(theirs, body) is not None:
                np.testing.assert_allclose(ours[1], transform(theirs, body)[1], atol=1e-9)
    assert exported["/robot_description"][0][1].data == written["/robot_description"][0][1].data
    assert exported["/mission/targets"], "the tasks' references"


def test_an_older_log_needs_its_world(logged, tmp_path, capsys):
    folder, written, _ = logged
    lines = (folder / "events.jsonl").read_text().splitlines()
    start = json.loads(lines[0])
    del start["world"]
    older = tmp_path / "older"
    older.mkdir()
    (older / "events.jsonl").write_text("\n".join([json.dumps(start)] + lines[1:]) + "\n")
    (older / "timeseries.parquet").write_bytes((folder / "timeseries.parquet").read_bytes())
    assert main(["export", str(older), "--mcap"]) == 1
    err = capsys.readouterr().err
    assert "does not say which world the run was on" in err and "--world" in err
    assert main(["export", str(older), "--mcap", "--world", "bazar/sophia.yaml"]) == 0
    assert capsys.readouterr().out.strip() == str(older / "run.mcap")
    exported = read_mcap(older / "run.mcap")
    assert len(exported["/joint_states"]) == len(written["/joint_states"])


def test_what_is_not_a_log_is_a_clear_error(tmp_path, capsys):
    assert main(["export", str(tmp_path), "--mcap"]) == 1
    assert f"{tmp_path}: no events.jsonl here" in capsys.readouterr().err
    assert main(["export", str(tmp_path)]) == 2
    assert "--mcap" in capsys.readouterr().err


def test_a_run_s_own_mcap_is_not_written_over_unless_asked(logged, tmp_path, capsys):
    folder, _, _ = logged
    before = (folder / "run.mcap").read_bytes()
    assert main(["export", str(folder), "--mcap"]) == 1
    err = capsys.readouterr().err
    assert f"{folder / 'run.mcap'} exists (the run wrote it" in err and "--replace" in err
    assert (folder / "run.mcap").read_bytes() == before
    copy = tmp_path / "copy"
    copy.mkdir()
    for name in ("events.jsonl", "timeseries.parquet", "run.mcap"):
        (copy / name).write_bytes((folder / name).read_bytes())
    assert main(["export", str(copy), "--mcap", "--replace"]) == 0
    assert read_mcap(copy / "run.mcap")["/joint_states"]


@pytest.mark.parametrize("command", ["export", "plot"])
def test_a_damaged_or_missing_log_is_a_one_line_error(logged, tmp_path, capsys, command):
    """A time series cut short, a file given for the folder, an output that cannot be
    written: one line that names the file, exit code 1, no traceback."""
    folder, _, _ = logged
    cut = tmp_path / "cut"
    cut.mkdir()
    (cut / "events.jsonl").write_bytes((folder / "events.jsonl").read_bytes())
    (cut / "timeseries.parquet").write_bytes((folder / "timeseries.parquet").read_bytes()[:2000])
    extra = ["--mcap"] if command == "export" else ["-o", str(tmp_path / "figures")]
    assert main([command, str(cut), *extra]) == 1
    err = capsys.readouterr().err
    assert f"{cut / 'timeseries.parquet'}: not a readable Parquet file" in err
    assert len(err.strip().splitlines()) == 1
    if command == "export":
        assert main(["export", str(folder / "events.jsonl"), "--mcap"]) == 1
        assert "not a folder" in capsys.readouterr().err
        assert main(["export", str(folder), "--mcap", "-o",
                     str(tmp_path / "missing" / "x.mcap")]) == 1
        assert "cannot write" in capsys.readouterr().err


@pytest.mark.parametrize("command", ["export", "plot"])
@pytest.mark.parametrize("damage, message", [
    ("reversed", "timeseries.parquet: time does not rise at cycle 1: 0.005 s after 0.01 s"),
    ("no state", "timeseries.parquet: rows without a state"),
])
def test_rows_out_of_order_or_without_a_state_are_refused(logged, tmp_path, capsys,
                                                         damage, message, command):
    """A time series whose rows go back in time, or have no state, is a damaged log:
    one line, exit code 1, and no file that would show it wrongly."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    folder, _, _ = logged
    table = pq.read_table(folder / "timeseries.parquet").slice(0, 10)
    if damage == "reversed":
        table = table.take(pa.array([0, 2, 1] + list(range(3, 10))))
    else:
        states = table.column("state").to_pylist()
        states[3] = None
        table = table.set_column(table.schema.get_field_index("state"), "state",
                                 pa.array(states, pa.string()))
    damaged = tmp_path / "damaged"
    damaged.mkdir()
    (damaged / "events.jsonl").write_bytes((folder / "events.jsonl").read_bytes())
    pq.write_table(table, damaged / "timeseries.parquet")
    extra = ["--mcap"] if command == "export" else ["-o", str(tmp_path / "figures")]
    assert main([command, str(damaged), *extra]) == 1
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1, err
    assert not (damaged / "run.mcap").exists() and not (tmp_path / "figures").exists()
