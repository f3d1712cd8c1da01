"""``robocop-mission plot``: the figures' structure on a real composed run (panels per
joint group and per error unit, distinct colours, a legend like the bands, one strip
row per machine, the final state as a marker) and the SVG option."""

import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import pytest
from matplotlib.colors import to_rgba

from robocop_dsl.runtime.plot import BAND_ALPHA, figures, joint_panels

REPO = Path(__file__).resolve().parent.parent


def robocop(*args):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", *map(str, args)],
                          capture_output=True, text=True, cwd=REPO, check=False)


@pytest.fixture(scope="module")
def parallel_log(tmp_path_factory):
    """A logged run of the parallel dual-arm mission (regions, nested machines)."""
    log = tmp_path_factory.mktemp("parallel") / "log"
    done = robocop("run", "missions/dual_arm_parallel.mission", "--log", log)
    assert done.returncode == 0, done.stderr
    return log


@pytest.fixture(scope="module")
def drawn(parallel_log):
    made = dict(figures(parallel_log))
    yield made
    for figure in made.values():
        plt.close(figure)


def signal_colours(ax):
    """The colours of an axes' signals (the final state's dashed line is not one)."""
    return [to_rgba(line.get_color()) for line in ax.get_lines()
            if not line.get_label().startswith("_")]


def panels(figure):
    """The signal panels: every axes but the states' strip (the first)."""
    return figure.axes[1:]


def test_one_panel_per_joint_group_with_distinct_colours(drawn):
    for name in ("joint_positions", "velocity_commands"):
        figure = drawn[name]
        assert [ax.get_title(loc="left") for ax in panels(figure)] == [
            "bazar_left_arm", "bazar_right_arm", "bazar_ptu"]
        for ax in panels(figure):
            colours = signal_colours(ax)
            assert len(colours) == len(set(colours)) > 1
            assert "[rad or m]" in ax.get_ylabel() or "[rad/s or m/s]" in ax.get_ylabel()
        assert [t.get_text() for t in panels(figure)[0].get_legend().get_texts()] == [
            f"bazar_left_joint_{i}" for i in range(1, 8)]
        assert figure.axes[-1].get_xlabel() == "mission time [s]"


def test_task_errors_are_split_by_unit(drawn):
    figure = drawn["task_errors"]
    labels = [ax.get_ylabel() for ax in panels(figure)]
    assert all("[" in label and "]" in label for label in labels)
    tasks = {ax.get_ylabel(): [t.get_text() for t in ax.get_legend().get_texts()]
             for ax in panels(figure)}
    assert sorted(tasks) == ["angle error [rad]", "position error [m]"]
    assert sorted(tasks["angle error [rad]"]) == [
        "arms", "left_tool.orientation", "right_tool.orientation", "watch"]
    assert sorted(tasks["position error [m]"]) == ["left_tool.position", "right_tool.position"]
    for ax in panels(figure):
        colours = signal_colours(ax)
        assert len(colours) == len(set(colours)) > 1


def test_one_strip_row_per_machine(drawn):
    strip = drawn["joint_positions"].axes[0]
    assert [t.get_text() for t in strip.get_yticklabels()] == [
        "mission", "home", "both/left", "both/right", "both/head", "back"]


def test_the_legend_matches_the_bands(drawn):
    """Translucent patches with the bands' colours and opacity, every state drawn once,
    the final state as a marker."""
    figure = drawn["joint_positions"]
    [legend] = figure.legends
    entries = dict(zip([t.get_text() for t in legend.get_texts()], legend.legend_handles))
    assert "done (final, success)" in entries
    assert entries["done (final, success)"].get_marker() == "D"
    bands = {}
    for patch in panels(figure)[0].patches:
        bands.setdefault(to_rgba(patch.get_facecolor(), 1), patch.get_alpha())
    for state in ("home", "both", "back"):
        handle = entries[state]
        assert handle.get_alpha() == BAND_ALPHA
        assert bands[to_rgba(handle.get_facecolor(), 1)] == BAND_ALPHA
    strip = figure.axes[0]
    widths = [bar.get_width() for bar in strip.patches]
    assert min(widths) > 0
    assert "done" not in entries


def test_svg_figures(parallel_log, tmp_path):
    done = robocop("plot", parallel_log, "--format", "svg", "-o", tmp_path)
    assert done.returncode == 0, done.stderr
    written = done.stdout.split()
    assert [Path(p).name for p in written] == [
        "joint_positions.svg", "velocity_commands.svg", "task_errors.svg"]
    for path in written:
        assert "<svg" in Path(path).read_text()[:1000]


def test_long_groups_are_cut_in_panels_of_ten():
    joints = [f"arm_joint_{i}" for i in range(1, 15)] + ["panda_joint1", "head_pan"]
    assert [(title, len(members)) for title, members in joint_panels(joints)] == [
        ("arm (1)", 10), ("arm (2)", 4), ("panda", 1), ("head", 1)]


def test_a_panel_per_declared_joint_group(tmp_path):
    """The world's groups the log lists give the panels: BAZAR's two arms and its
    pan-tilt unit, not its 16 joints by name; the largest groups of ten at most that
    share no joint, in the world's order."""
    from robocop_dsl.runtime import load_mission
    from robocop_dsl.runtime.log import RunLogger, check_timeseries
    from robocop_dsl.runtime.plot import _declared_groups

    runner = load_mission(REPO / "missions" / "pickup.mission").runner()
    runner.add_observer(RunLogger(tmp_path, runner.joint_names))
    runner.run(duration=0.05)
    declared = _declared_groups(check_timeseries(tmp_path))
    assert set(declared) == {"bazar_left_arm", "bazar_right_arm", "bazar_arms", "bazar_ptu",
                             "bazar_upper_joints"}
    joints = list(runner.joint_names)
    assert [(title, len(members)) for title, members in joint_panels(joints, declared)] == [
        ("bazar_left_arm", 7), ("bazar_right_arm", 7), ("bazar_ptu", 2)]
    figure = dict(figures(tmp_path))["joint_positions"]
    assert [ax.get_title(loc="left") for ax in panels(figure)] == [
        "bazar_left_arm", "bazar_right_arm", "bazar_ptu"]
