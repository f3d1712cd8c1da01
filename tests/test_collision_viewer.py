"""Collision lines in the viewer: between the witness points of the pairs within
influence, coloured by closeness, in replays and in the live scene's frames."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from robocop_dsl.viewer import read_replay
from robocop_dsl.viewer.collisions import BANDS, CollisionLines, band_path, slot_path

REPO = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def replay(tmp_path_factory):
    path = tmp_path_factory.mktemp("replay") / "through.html"
    done = subprocess.run([sys.executable, "-m", "robocop_dsl", "run",
                           "missions/through_the_table.mission", "--record", path],
                          capture_output=True, text=True, cwd=REPO)
    assert done.returncode == 0, done.stdout + done.stderr
    return read_replay(path)


def _tracks(commands, path):
    (animation,) = [c for c in commands if c["type"] == "set_animation"]
    for clip in animation["animations"]:
        if clip["path"].endswith(path):
            return {t["name"]: [k["value"] for k in t["keys"]] for t in clip["clip"]["tracks"]}
    return {}


def test_the_replay_stretches_a_red_line_down_to_the_workbench(replay):
    objects = [c["path"] for c in replay if c["type"] == "set_object"]
    assert any(p.endswith(band_path(0, 0)) for p in objects)
    line = _tracks(replay, slot_path(0))
    lengths = [scale[1] for scale in line[".scale"]]
    assert 0.019 <= lengths[-1] < 0.025    # the mission ends below 2.5 cm, at 2 cm or more
    assert max(lengths) > 0.06                               # it came in from influence
    red = _tracks(replay, band_path(0, 0))[".visible"]
    yellow = _tracks(replay, band_path(0, len(BANDS) - 1))[".visible"]
    assert red[-1] and not red[0] and any(yellow)
    heights = [position[2] for position in line[".position"]]
    assert min(heights) > 0.74                              # above the workbench surface


def test_lines_join_the_witness_points_of_the_closest_pairs(bazar):
    lines = CollisionLines(bazar, [("bazar_left_arm", "bazar_left_arm", 0.02, 0.1)])
    drawn = lines.lines(bazar.initial_configuration())
    shown = [path for path, visible in drawn.visible.items() if visible]
    assert shown == [band_path(0, 2)]                      # 7.96 cm: the far band
    matrix = drawn.transforms()[slot_path(0)]
    ends = [matrix @ np.array([0, s / 2, 0, 1.0]) for s in (-1, 1)]
    assert np.linalg.norm(ends[1][:3] - ends[0][:3]) == pytest.approx(0.0796, abs=1e-3)


def test_the_live_scene_shows_the_line_of_the_last_cycle(bazar):
    from test_viewer_live import SYNC, server_scene

    from robocop_dsl.runtime import load_mission
    from robocop_dsl.viewer import LiveViewer, ViewerOptions

    runner = load_mission(REPO / "missions" / "through_the_table.mission",
                          world=bazar).runner()
    with LiveViewer(bazar, options=ViewerOptions(period=0.01)) as viewer:
        runner.add_observer(viewer)
        assert runner.run(duration=30.0).outcome == "success"
        assert viewer.sync(SYNC) and viewer.problems == []
        commands = server_scene(viewer.zmq_url)
    matrix = [np.array(c["matrix"]).reshape(4, 4).T for c in commands
              if c["type"] == "set_transform" and c["path"].endswith(slot_path(0))][-1]
    assert 0.019 <= np.linalg.norm(matrix[:3, 1]) < 0.025     # the stretch
    red = [c["value"] for c in commands
           if c["type"] == "set_property" and c["path"].endswith(band_path(0, 0))]
    assert red[-1] is True
