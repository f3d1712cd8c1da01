"""The force missions through the command line, judged from their logs: the Panda
presses the table at 10 N and records where it touched; BAZAR seats the part by force
three times, counting with a var."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from robocop_dsl.runtime import read_timeseries
from robocop_dsl.world import load_world

REPO = Path(__file__).resolve().parent.parent
MISSIONS = REPO / "missions"
TABLE_TOP = 0.75
"""The Panda's table top [m] (panda/panda_on_table.yaml)."""


def run(*args):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", "run", *map(str, args)],
                          capture_output=True, text=True, cwd=REPO)


def events(folder) -> list:
    return [json.loads(line) for line in (folder / "events.jsonl").read_text().splitlines()]


def last_second_of(log, state: str) -> np.ndarray:
    """The rows of the last second spent in ``state``."""
    times, states = np.asarray(log["time"]), np.asarray(log["state"])
    inside = states == state
    end = times[inside].max()
    return inside & (times > end - 1.0)


@pytest.fixture(scope="module", params=["weighted", "strict"])
def press(request, tmp_path_factory):
    folder = tmp_path_factory.mktemp(f"press_{request.param}")
    done = run(MISSIONS / "panda_press.mission", "--hierarchy", request.param,
               "--log", folder)
    assert done.returncode == 0, done.stdout + done.stderr
    return read_timeseries(folder), events(folder)


def test_the_fingertips_press_the_table_at_10_n(press):
    """The median of the last second of contact is 10 N within 1 N (a negative z: what
    the hand exerts on the table)."""
    log, _ = press
    pressing = last_second_of(log, "hold")
    assert np.median(np.asarray(log["force.panda_hand.z"])[pressing]) == pytest.approx(
        -10.0, abs=1.0)


def test_the_recorded_contact_height_is_the_table_top(press):
    log, found = press
    assert log["var.contact_z"][-1] == pytest.approx(TABLE_TOP, abs=0.005)
    (assigned,) = [e["value"] for e in found if e["kind"] == "assign"
                   and e["var"] == "contact_z"]
    assert assigned == log["var.contact_z"][-1]
    (message,) = [e["message"] for e in found if e["kind"] == "log"]
    assert message.startswith("touched the table at 0.75")


def test_x_and_y_hold_while_pressing(press):
    """Above the force task, the position task keeps the tool where it touched."""
    log, _ = press
    pressing = np.isin(np.asarray(log["state"]), ["settle", "hold"])
    world = load_world("panda/panda_press.yaml")
    xy = np.array([world.body_pose("panda_hand_tcp", q).translation[:2]
                   for q in _configurations(world, log, pressing)])
    assert np.abs(xy - xy[0]).max() < 0.002


def _configurations(world, log, rows):
    """The world's configurations at the logged rows (the controlled joints)."""
    q0 = world.initial_configuration()
    for row in np.flatnonzero(rows):
        q = q0.copy()
        for column, values in log.items():
            if column.startswith("q."):
                joint = world.model.joints[world.model.getJointId(column[2:])]
                q[joint.idx_q] = values[row]
        yield q


def test_bazar_seats_the_part_three_times_and_counts(tmp_path):
    done = run(MISSIONS / "bazar_seat.mission", "--log", tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    log, found = read_timeseries(tmp_path), events(tmp_path)
    counted = [e["value"] for e in found if e["kind"] == "assign" and e["var"] == "parts_done"]
    assert counted == [1, 2, 3]
    assert log["var.parts_done"][-1] == 3
    seated = [e["message"] for e in found if e["kind"] == "log"]
    assert [m.split(",")[0] for m in seated] == [f"seated {n} of 3" for n in (1, 2, 3)]
    world = load_world("bazar/sophia_seat.yaml")
    seat = world.body_pose("seat_point", world.initial_configuration()).translation
    part = np.array([log[f"pose.part_body.{a}"][-1] for a in "xyz"])
    assert np.linalg.norm(part - seat) < 0.005
    holding = np.asarray(log["state"]) == "hold"
    force = np.asarray(log["force.bazar_left_hankamp_tool_robot_side.z"])[holding]
    assert np.median(force) == pytest.approx(-20.0, abs=2.0)
