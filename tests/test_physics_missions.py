"""Missions run in MuJoCo through the command line, judged from their logs: the Panda
picks the cube by friction (and does not with open fingers), BAZAR carries the welded
part to the drop point (and drops it when it lets go early), runs repeat bit for bit,
the replay draws the cube where physics put it."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from robocop_dsl.runtime import read_timeseries
from robocop_dsl.viewer import read_replay
from robocop_dsl.viewer.geometry import body_path
from robocop_dsl.world import load_world
from test_viewer_replay import PERIOD, animated_pose, frame_rows, tracks_by_path

REPO = Path(__file__).resolve().parent.parent
MISSIONS = REPO / "missions"
TIMES = ("cycle_time", "compute_time")


def run(*args):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", "run", *map(str, args)],
                          capture_output=True, text=True, cwd=REPO)


def positions(log, body) -> np.ndarray:
    """The logged world positions [m] of a free body, one row per cycle."""
    return np.column_stack([log[f"pose.{body}.{axis}"] for axis in "xyz"])


def events(folder) -> list:
    return [json.loads(line) for line in (folder / "events.jsonl").read_text().splitlines()]


def variant(tmp_path, mission: str, old: str, new: str) -> Path:
    """A copy of a bundled mission with ``old`` replaced by ``new`` (its world found
    along the robots path as the original's is)."""
    text = (MISSIONS / mission).read_text()
    assert old in text
    path = tmp_path / mission
    path.write_text(text.replace(old, new))
    return path


@pytest.fixture(scope="module")
def pick(tmp_path_factory):
    folder = tmp_path_factory.mktemp("pick")
    done = run(MISSIONS / "panda_pick.mission", "--log", folder / "log", "--record",
               folder / "pick.html")
    return done, folder


def test_the_panda_picks_the_cube_by_friction(pick):
    done, folder = pick
    assert done.returncode == 0, done.stdout + done.stderr
    log = read_timeseries(folder / "log")
    cube = positions(log, "cube_body")
    assert cube[0] == pytest.approx([0.5, 0.0, 0.77], abs=1e-3)
    world = load_world("panda/panda_pick.yaml")
    lift = world.body_pose("lift_point", world.initial_configuration()).translation
    assert np.linalg.norm(cube[-1] - lift) < 0.02
    assert cube[-1][2] > 0.93                           # 16 cm above the table
    # the fingers hold it by its faces, 2 cm from the middle each
    assert log["q.panda_finger_joint1"][-1] == pytest.approx(0.02, abs=2e-3)
    assert [e["to"] for e in events(folder / "log") if e["kind"] == "transition"] == [
        "above", "descend", "close", "lift", "done"]


def test_with_fingers_that_stay_open_the_cube_stays_on_the_table(tmp_path):
    mission = variant(tmp_path, "panda_pick.mission", "let closed = [0] cm",
                      "let closed = [4] cm")
    done = run(mission, "--log", tmp_path / "log")
    assert done.returncode == 1, done.stdout + done.stderr
    assert "final state: failed" in done.stdout
    cube = positions(read_timeseries(tmp_path / "log"), "cube_body")
    assert np.abs(cube - [0.5, 0.0, 0.77]).max() < 1e-3


def test_the_replay_draws_the_cube_where_physics_put_it(pick):
    """Each frame of the recorded replay shows the cube at its logged pose."""
    _, folder = pick
    log = read_timeseries(folder / "log")
    tracks, _ = tracks_by_path(read_replay(folder / "pick.html"))
    cube = tracks[f"/meshcat/{body_path('cube_body')}"]
    frames = [frame for frame, _ in cube[".position"]]
    rows = frame_rows(log, len(frames))
    moved = 0
    for frame, row in zip(frames, rows):
        drawn = animated_pose(cube, frame)[:3, 3]
        logged = [log[f"pose.cube_body.{a}"][row] for a in "xyz"]
        assert np.allclose(drawn, logged, atol=1e-6)
        moved += not np.allclose(logged, [0.5, 0.0, 0.77], atol=1e-3)
    assert moved > 10


def test_runs_repeat_bit_for_bit(pick, tmp_path):
    """The same mission and world twice: identical time series (but for the wall-clock
    columns) and identical events."""
    _, folder = pick
    done = run(MISSIONS / "panda_pick.mission", "--log", tmp_path / "log")
    assert done.returncode == 0
    first, second = read_timeseries(folder / "log"), read_timeseries(tmp_path / "log")
    assert first.keys() == second.keys()
    for column in first:
        if column not in TIMES:
            assert np.array_equal(np.asarray(first[column]), np.asarray(second[column]),
                                  equal_nan=np.asarray(first[column]).dtype.kind == "f"), column
    assert events(folder / "log") == events(tmp_path / "log")


def test_kinematic_runs_repeat_bit_for_bit_too(tmp_path):
    """The controller alone repeats itself: ProxQP runs in its portable build, whose
    answers do not depend on how the heap aligned its memory."""
    for attempt in range(2):
        assert run(MISSIONS / "panda_reach.mission", "--log", tmp_path / str(attempt)
                   ).returncode == 0
    first, second = read_timeseries(tmp_path / "0"), read_timeseries(tmp_path / "1")
    for column in set(first) - set(TIMES):
        assert np.array_equal(np.asarray(first[column]), np.asarray(second[column]),
                              equal_nan=np.asarray(first[column]).dtype.kind == "f"), column


def test_proxqp_is_loaded_in_its_portable_build():
    done = subprocess.run([sys.executable, "-c", "import robocop_dsl.control.solvers, "
                           "qpsolvers, proxsuite; print(proxsuite._submodule.__name__)"],
                          capture_output=True, text=True)
    assert done.stdout.strip() == "proxsuite.proxsuite_pywrap"


@pytest.fixture(scope="module")
def drop_point():
    world = load_world("bazar/sophia_physics.yaml")
    return world.body_pose("drop_point", world.initial_configuration()).translation


def test_bazar_carries_the_welded_part_to_the_drop_point(tmp_path, drop_point):
    done = run(MISSIONS / "pickup.mission", "--world", "bazar/sophia_physics.yaml",
               "--log", tmp_path / "log")
    assert done.returncode == 0, done.stdout + done.stderr
    part = positions(read_timeseries(tmp_path / "log"), "part_body")
    assert np.linalg.norm(part[-1] - drop_point) < 0.01
    assert part[:, 2].max() > drop_point[2] + 0.14      # carried at carry height


def test_bazar_drops_the_part_it_lets_go_early(tmp_path, drop_point):
    """Released as soon as it is lifted, the part falls back on the workbench, far from
    the drop point."""
    mission = variant(tmp_path, "pickup.mission", 'enter { log "part grasped" }',
                      'enter { log "part grasped"\n detach part_body }')
    done = run(mission, "--world", "bazar/sophia_physics.yaml", "--log", tmp_path / "log")
    assert done.returncode == 0, done.stdout + done.stderr
    log = read_timeseries(tmp_path / "log")
    part = positions(log, "part_body")
    released = next(e["time"] for e in events(tmp_path / "log")
                    if e["kind"] == "action" and e["action"] == "detach")
    after = np.asarray(log["time"]) > released + 0.5
    assert np.allclose(part[after][:, 2], 0.76, atol=2e-3)      # on the workbench
    assert np.linalg.norm(part[-1] - drop_point) > 0.1


def test_a_cascade_is_refused_in_physics(tmp_path):
    """Each controller of a cascade has its own driver; one physics cannot be split
    between them: the check before the run says so, without a traceback."""
    world = tmp_path / "cascade_physics.yaml"
    world.write_text("models:\n  - include: bazar/sophia_cascade.yaml\nprocessors:\n"
                     "  arms_driver: {type: mujoco, options: {joint_group: bazar_arms}}\n")
    mission = variant(tmp_path, "pickup_cascade.mission",
                      "exit  { attach part_body to bazar_left_hankamp_tool_object_side }", "")
    mission.write_text(mission.read_text().replace("exit  { detach part_body }", ""))
    done = run(mission, "--world", world)
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert "error[missing-driver]" in done.stderr
    assert "one physics cannot be split between the threads of a cascade" in done.stderr
