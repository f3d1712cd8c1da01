"""Run-time values as a user meets them: missions with vars run through the command
line, judged from their events and logs; a behaviour's var is one per instance; a
target and a log text read vars when they run."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from robocop_dsl.compile import check_file
from robocop_dsl.world import load_world

REPO = Path(__file__).resolve().parent.parent
MISSIONS = REPO / "tests" / "fixtures" / "missions"


def run(*args):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", "run", *map(str, args)],
                          capture_output=True, text=True, cwd=REPO)


def events(folder) -> list:
    return [json.loads(line) for line in (folder / "events.jsonl").read_text().splitlines()]


@pytest.fixture(scope="module")
def laps(tmp_path_factory):
    folder = tmp_path_factory.mktemp("laps")
    done = run(MISSIONS / "laps.mission", "--log", folder)
    assert done.returncode == 0, done.stdout + done.stderr
    return done, events(folder)


def test_every_assignment_is_an_event_with_its_value(laps):
    _, found = laps
    assigned = [(e["var"], e["value"]) for e in found if e["kind"] == "assign"]
    assert [value for var, value in assigned if var == "laps"] == [1, 2, 3]
    lowest = [value for var, value in assigned if var == "lowest"]
    assert lowest == pytest.approx([0.03, 0.01])          # 5 cm, minus 2 cm a lap
    seen = [value for var, value in assigned if var == "seen"]
    assert len(seen) == 2 and all(len(v) == 3 for v in seen)


def test_a_target_reads_the_var_when_its_action_runs(laps):
    """Each lap goes 2 cm lower: where the hand was seen is the target point raised by
    the var's value at the lap's start."""
    _, found = laps
    world = load_world("panda/panda_on_table.yaml")
    point = world.body_pose("target_point", world.initial_configuration()).translation
    seen = [np.array(e["value"]) for e in found if e["kind"] == "assign" and e["var"] == "seen"]
    assert seen[0] == pytest.approx(point + [0, 0, 0.05], abs=2e-3)
    assert seen[1] == pytest.approx(point + [0, 0, 0.03], abs=2e-3)


def test_log_texts_print_vars_and_constants_with_their_units(laps):
    done, found = laps
    logged = [e["message"] for e in found if e["kind"] == "log"]
    assert logged[0] == "lap 1 from 1.34027 m, step 2 cm"
    assert logged[1].startswith("at [0.45") and logged[1].endswith("] m, next 0.03 m")
    assert "log: lap 3 from 1.34027 m, step 2 cm" in done.stdout + done.stderr


def test_a_behaviours_var_is_one_per_instance(tmp_path):
    done = run(MISSIONS / "bounce_counts.mission", "--log", tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    found = events(tmp_path)
    by_var: dict = {}
    for event in found:
        if event["kind"] == "assign":
            by_var.setdefault(event["var"], []).append(event["value"])
    assert by_var == {"first/tries": [1, 2], "second/tries": [1, 2, 3],
                      "total": [1, 2, 3, 4, 5]}
    assert [e["message"] for e in found if e["kind"] == "log"][-1] == "try 3 of 3, 5 in all"


def test_the_example_missions_check_clean():
    for path in MISSIONS.glob("*.mission"):
        assert check_file(path).diagnostics == (), path


def test_each_var_is_a_column_of_the_time_series(laps, tmp_path):
    """``var.NAME`` per cycle (a position in three), NaN until assigned, in SI with its
    unit in the field's metadata; the last row holds the last values assigned."""
    import pyarrow.parquet as pq

    from robocop_dsl.runtime import read_timeseries

    done, found = laps
    folder = Path(done.args[done.args.index("--log") + 1])
    log = read_timeseries(folder)
    assert [c for c in log if c.startswith("var.")] == [
        "var.laps", "var.start_z", "var.lowest", "var.seen.x", "var.seen.y", "var.seen.z"]
    assert log["var.laps"][0] == 1 and log["var.laps"][-1] == 3
    assert np.isnan(log["var.seen.z"][0])
    last = [e["value"] for e in found if e["kind"] == "assign" and e["var"] == "seen"][-1]
    assert [log[f"var.seen.{a}"][-1] for a in "xyz"] == last
    schema = pq.read_schema(folder / "timeseries.parquet")
    assert schema.field("var.lowest").metadata == {b"unit": b"m"}
    assert schema.field("var.laps").metadata is None
