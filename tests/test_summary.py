"""The end-of-run summary: the enabled tasks' final errors, and for a run that did not
succeed, the clause that fired and how far the others were from holding."""

import math
import re
import subprocess
import sys
from pathlib import Path

import pytest

from robocop_dsl.runtime import load_mission
from robocop_dsl.runtime.summary import SummaryWatch, format_quantity

REPO = Path(__file__).resolve().parent.parent

HEADER = '''mission m
world "bazar/sophia.yaml"
task left_tool: body_pose(bazar_left_hankamp_tool_object_side) {
    interpolator = otg(max_velocity = 0.2 m/s, max_acceleration = 0.5 m/s^2)
    feedback     = proportional(gain = 5)
}
'''

TIMEOUT = HEADER + '''
state reach {
    enter {
        enable left_tool
        left_tool.target = pickup_point offset [0, 0, 10] cm
    }
    when left_tool.reached and left_tool.position_error < 1 mm -> done
    when elapsed > 0.5 s -> failed
}
final done
final failed: failure
'''

NESTED = HEADER + '''
state reach {
    enter { enable left_tool }
    start moving
    state moving {
        enter { left_tool.target = pickup_point offset [0, 0, 10] cm }
        when left_tool.reached -> there
        when elapsed > 0.3 s -> missed
    }
    final there
    final missed
    when reach.there -> done
    when reach.missed -> failed
}
final done
final failed: failure
'''


def robocop(*args):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", *map(str, args)],
                          capture_output=True, text=True, cwd=REPO, check=False)


def write(tmp_path, text, name="m.mission"):
    path = tmp_path / name
    path.write_text(text)
    return path


def watched_run(path, duration=None):
    mission = load_mission(path)
    runner = mission.runner()
    watch = SummaryWatch(mission.spec)
    runner.add_observer(watch)
    result = runner.run(duration=duration)
    return runner, result, watch.summary


def test_a_timeout_names_its_clause_and_how_far_the_other_was(tmp_path):
    """The clause that fired, and the other clause's conditions measured at that cycle:
    the task's error is the real one, far above the 1 mm it waited for."""
    runner, result, summary = watched_run(write(tmp_path, TIMEOUT))
    assert result.outcome == "failure"
    [fired] = summary.fired
    assert (fired.source, fired.target, fired.condition) == ("reach", "failed",
                                                             "elapsed > 0.5 s")
    assert fired.time == pytest.approx(0.505)
    [other] = fired.others
    assert other.target == "done"
    reached, error = other.atoms
    assert reached.text == "left_tool.reached" and not reached.holds
    assert error.text == "left_tool.position_error < 1 mm" and not error.holds
    measured = float(error.value.split()[0])
    assert measured > 1.0   # metres: the tool is still far from the point
    [task] = summary.tasks
    assert task.name == "left_tool" and not task.reached
    assert [label for label, _, _ in task.errors] == ["position", "orientation"]
    position = task.errors[0][1]
    assert position == pytest.approx(measured, abs=1e-3)   # the position part
    assert runner.controller.task("left_tool").position_error == pytest.approx(position,
                                                                               abs=0.05)


def test_a_nested_timeout_is_reported_innermost_first(tmp_path):
    """The parent's clause read the nested outcome; the summary shows the nested
    timeout that produced it, then the parent's clause."""
    _, result, summary = watched_run(write(tmp_path, NESTED))
    assert result.outcome == "failure"
    inner, outer = summary.fired
    assert (inner.source, inner.target, inner.condition) == ("reach/moving",
                                                             "reach/missed",
                                                             "elapsed > 0.3 s")
    assert (outer.source, outer.target, outer.condition) == ("reach", "failed",
                                                             "reach.missed")
    assert [(c.state, c.text) for c in inner.others] == [
        ("reach/moving", "left_tool.reached"), ("reach", "reach.there"),
        ("reach", "reach.missed")]
    assert [c.text for c in outer.others] == ["reach.there"]
    [there] = outer.others[0].atoms
    assert not there.holds and there.value == "no (in reach/missed)"


def test_a_stopped_run_shows_what_each_active_clause_waited_for(tmp_path):
    """``--duration`` came first: every clause of the active state, with the elapsed
    time it had reached."""
    _, result, summary = watched_run(write(tmp_path, TIMEOUT), duration=0.2)
    assert result.outcome == "stopped"
    assert summary.fired == ()
    texts = [c.text for c in summary.pending]
    assert texts == ["left_tool.reached and left_tool.position_error < 1 mm", "elapsed > 0.5 s"]
    [elapsed] = summary.pending[1].atoms
    assert not elapsed.holds
    assert elapsed.value.endswith(" s") and float(elapsed.value.split()[0]) < 0.5


def test_run_prints_the_summary_with_units(tmp_path):
    """What a user sees: the tasks table and the clauses with their measures."""
    done = robocop("run", write(tmp_path, TIMEOUT))
    assert done.returncode == 1, done.stderr
    out = done.stdout
    assert "tasks at the end" in out
    row = next(line for line in out.splitlines() if line.strip().startswith("left_tool"))
    assert "body_pose" in row and re.search(r"position [\d.]+ m, orientation [\d.]+ deg", row)
    assert row.rstrip().endswith("no")
    assert "fired at 0.505 s: reach -> failed  (elapsed > 0.5 s)" in out
    assert re.search(r"left_tool\.position_error < 1 mm: [\d.]+ m  does not hold", out)


def test_a_success_lists_the_tasks_reached():
    """The pickup ends with the arms' posture task reached, its error in degrees."""
    done = robocop("run", "missions/pickup.mission")
    assert done.returncode == 0, done.stderr
    row = next(line for line in done.stdout.splitlines() if line.strip().startswith("arms "))
    assert "joint_position" in row and "bazar_arms" in row
    assert re.search(r"[\d.]+ deg", row) and row.rstrip().endswith("yes")
    assert "fired at" not in done.stdout


def test_a_cascade_lists_the_tasks_of_every_controller():
    """The cascaded pickup ends with the arms' posture task (the state machine's
    controller) and the head's gaze (a controller of its own) enabled: both are listed,
    the left tool (disabled on the way back) is not."""
    done = robocop("run", "missions/pickup_cascade.mission")
    assert done.returncode == 0, done.stderr
    table = done.stdout.split("tasks at the end")[1]
    rows = {line.split()[0]: line for line in table.splitlines()
            if line.strip() and line.split()[0] in ("arms", "watch", "left_tool")}
    assert set(rows) == {"arms", "watch"}
    assert "gaze" in rows["watch"] and "kinect2_rgb_optical_frame" in rows["watch"]
    assert re.search(r"[\d.]+ deg", rows["watch"]) and rows["watch"].rstrip().endswith("yes")


@pytest.mark.parametrize("value, unit, text", [
    (0.0042, "m", "4.2 mm"), (2.5, "m", "2.5 m"), (math.radians(3), "rad", "3 deg"),
    (15.0, "s", "15 s"), (float("nan"), "m", "n/a"), (3.0, "", "3")])
def test_quantities_read_in_the_units_a_user_writes(value, unit, text):
    assert format_quantity(value, unit) == text
