"""``plot`` and ``export --mcap`` on damaged copies of a real log: one line naming the
file and what is wrong, exit code 1, no traceback and no output left behind; a log of
one cycle is plotted, a last line cut short by a kill is tolerated."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from conftest import MISSIONS
from robocop_dsl.cli.main import main

REPO = Path(__file__).resolve().parent.parent
FILES = ("events.jsonl", "timeseries.parquet")
UNPRIVILEGED = ["setpriv", "--bounding-set=-dac_override,-dac_read_search",
                "--inh-caps=-dac_override,-dac_read_search"]


@pytest.fixture(scope="session")
def log(tmp_path_factory):
    """Two seconds of the pickup, logged (the duration ends it: exit code 1)."""
    folder = tmp_path_factory.mktemp("damaged") / "log"
    assert main(["run", str(MISSIONS / "pickup.mission"), "--log", str(folder),
                 "--duration", "2"]) == 1
    return folder


def copy_of(log, tmp_path) -> Path:
    folder = tmp_path / "copy"
    folder.mkdir()
    for name in FILES:
        shutil.copy(log / name, folder / name)
    return folder


def rewrite_table(folder, change) -> None:
    table = pq.read_table(folder / "timeseries.parquet")
    pq.write_table(change(table), folder / "timeseries.parquet")


def set_column(name, values):
    def change(table):
        return table.set_column(table.column_names.index(name), name,
                                pa.array(values(table.num_rows)))
    return change


def append_line(folder, line: str) -> None:
    with open(folder / "events.jsonl", "a", encoding="utf-8") as events:
        events.write(line + "\n")


def with_metadata(key: bytes, value: bytes):
    def change(table):
        return table.replace_schema_metadata({**table.schema.metadata, key: value})
    return change


def binary_events(folder):
    (folder / "events.jsonl").write_bytes(b"\xce\x01\xff\n\x8f{\x00\n\xfe\xfa")


def events_folder(folder):
    (folder / "events.jsonl").unlink()
    (folder / "events.jsonl").mkdir()


DAMAGES = {
    "binary events": (binary_events, "events.jsonl: line 1 is not an event"),
    "events a folder": (events_folder, "events.jsonl: cannot be read (Is a directory)"),
    "a list line": (lambda f: append_line(f, "[1, 2]"), "is not an event"),
    "a string line": (lambda f: append_line(f, '"str"'), "is not an event"),
    "a null line": (lambda f: append_line(f, "null"), "is not an event"),
    "an event without time": (lambda f: append_line(f, '{"kind": "x", "cycle": 1}'),
                              "is not an event"),
    "no state": (lambda f: rewrite_table(f, lambda t: t.drop(["state"])),
                 "timeseries.parquet: no column state"),
    "no time": (lambda f: rewrite_table(f, lambda t: t.drop(["time"])),
                "timeseries.parquet: no column time"),
    "time of strings": (lambda f: rewrite_table(f, set_column("time", lambda n: ["x"] * n)),
                        "columns that are not numbers: time (string)"),
    "time NaN": (lambda f: rewrite_table(f, set_column("time", lambda n: np.full(n, np.nan))),
                 "column time holds values that are NaN"),
    "only a column a": (lambda f: pq.write_table(pa.table({"a": [1.0, 2.0]}),
                                                 f / "timeseries.parquet"),
                        "timeseries.parquet: no column"),
    "tasks metadata": (lambda f: rewrite_table(f, with_metadata(b"tasks", b"{x")),
                       "its tasks metadata is damaged"),
    "joint groups metadata": (lambda f: rewrite_table(f, with_metadata(b"joint_groups",
                                                                       b'{"a": 5}')),
                              "its joint_groups metadata is damaged"),
}


def arguments(command: str, folder: Path) -> list:
    return ([command, str(folder), "--mcap"] if command == "export"
            else [command, str(folder), "-o", str(folder / "figures")])


def assert_one_line_error(capsys, argv, *expected) -> str:
    assert main(argv) == 1
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1, err
    for text in expected:
        assert text in err
    return err


@pytest.mark.parametrize("command", ["plot", "export"])
@pytest.mark.parametrize("damage", DAMAGES)
def test_a_damaged_log_is_a_one_line_error(log, tmp_path, capsys, command, damage):
    folder = copy_of(log, tmp_path)
    change, message = DAMAGES[damage]
    change(folder)
    assert_one_line_error(capsys, arguments(command, folder), message)
    assert sorted(os.listdir(folder)) == sorted(FILES), "nothing written"


def test_an_export_needs_a_world_it_can_name_and_actions_it_can_replay(log, tmp_path,
                                                                      capsys):
    folder = copy_of(log, tmp_path)
    lines = (folder / "events.jsonl").read_text().splitlines()
    start = {**json.loads(lines[0]), "world": 5}
    (folder / "events.jsonl").write_text("\n".join([json.dumps(start)] + lines[1:]) + "\n")
    assert_one_line_error(capsys, arguments("export", folder),
                          "events.jsonl: the start event's world is not a file name")
    shutil.copy(log / "events.jsonl", folder / "events.jsonl")
    append_line(folder, json.dumps({"kind": "action", "time": 0.5, "cycle": 3,
                                    "action": "attach", "body": "cube"}))
    assert_one_line_error(capsys, arguments("export", folder),
                          "events.jsonl: the action at cycle 3 cannot be replayed")
    assert sorted(os.listdir(folder)) == sorted(FILES)


def test_a_log_of_one_cycle_is_plotted(log, tmp_path, capsys):
    folder = copy_of(log, tmp_path)
    rewrite_table(folder, lambda table: table.slice(0, 1))
    assert main(arguments("plot", folder)) == 0
    out, err = capsys.readouterr()
    assert err == ""
    assert sorted(Path(line).name for line in out.split()) == [
        "joint_positions.png", "task_errors.png", "velocity_commands.png"]


def test_a_log_of_no_cycle_has_nothing_to_plot(log, tmp_path, capsys):
    folder = copy_of(log, tmp_path)
    rewrite_table(folder, lambda table: table.slice(0, 0))
    assert_one_line_error(capsys, arguments("plot", folder),
                          f"{folder}: no cycle logged, nothing to plot")
    assert not (folder / "figures").exists()


@pytest.mark.parametrize("command", ["plot", "export"])
def test_a_last_line_cut_short_is_tolerated(log, tmp_path, capsys, command):
    folder = copy_of(log, tmp_path)
    with open(folder / "events.jsonl", "a", encoding="utf-8") as events:
        events.write('{"kind": "transi')
    assert main(arguments(command, folder)) == 0
    assert capsys.readouterr().err == ""


def test_figures_that_cannot_be_written_name_their_folder(log, tmp_path, capsys):
    taken = tmp_path / "taken"
    taken.write_text("")
    assert_one_line_error(capsys, ["plot", str(log), "-o", str(taken)],
                          f"{taken}: not a folder")
    assert_one_line_error(capsys, ["plot", str(log), "-o", "/proc/x"],
                          "/proc/x: cannot write the figures")


def test_an_export_that_cannot_be_written_leaves_nothing(log, tmp_path, capsys):
    folder = copy_of(log, tmp_path)
    (folder / "taken.mcap").mkdir()
    assert_one_line_error(capsys, ["export", str(folder), "--mcap", "-o",
                                   str(folder / "taken.mcap"), "--replace"],
                          f"cannot write {folder / 'taken.mcap'}")
    assert sorted(os.listdir(folder)) == sorted([*FILES, "taken.mcap"])


def run_unprivileged(*argv):
    """The command line, without the right to read or write what its mode forbids."""
    prefix = []
    if os.geteuid() == 0:
        if shutil.which("setpriv") is None:
            pytest.skip("root without setpriv: file modes are not enforced")
        prefix = UNPRIVILEGED
    return subprocess.run([*prefix, sys.executable, "-m", "robocop_dsl", *map(str, argv)],
                          capture_output=True, text=True, cwd=REPO, check=False)


@pytest.mark.parametrize("command", ["plot", "export"])
@pytest.mark.parametrize("unreadable", ["events.jsonl", "."])
def test_an_unreadable_log_is_a_one_line_error(log, tmp_path, command, unreadable):
    folder = copy_of(log, tmp_path)
    (folder / unreadable).chmod(0)
    try:
        done = run_unprivileged(*arguments(command, folder))
    finally:
        (folder / unreadable).chmod(0o755)
    assert done.returncode == 1
    assert len(done.stderr.strip().splitlines()) == 1, done.stderr
    assert str(folder) in done.stderr
    assert "cannot be read (Permission denied)" in done.stderr


def test_figures_in_a_folder_that_cannot_be_written(log, tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o555)
    done = run_unprivileged("plot", log, "-o", locked)
    assert done.returncode == 1
    assert len(done.stderr.strip().splitlines()) == 1, done.stderr
    assert f"{locked / 'joint_positions.png'}: cannot write the figures" in done.stderr
