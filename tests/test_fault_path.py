"""One fault path: whatever raises in the loop (an action, a task's interpolator, an
observer, the driver) ends the run with outcome ``fault`` and a message naming the
state and what raised; the robot holds, every observer's ``on_stop`` runs, the log is
complete and ``run`` exits 3, with a traceback only under ``--debug``."""

import subprocess
import sys
from pathlib import Path

import numpy as np

from conftest import write
from robocop_dsl.control.interpolators.linear import LinearInterpolator
from robocop_dsl.runtime import Observer, load_mission, read_events, read_timeseries

REPO = Path(__file__).resolve().parent.parent

CYCLE = """
mission cycle
world "bazar/sophia.yaml"

state carry {
    enter { attach part_body to drop_point }
    when elapsed > 20 ms -> loop { attach drop_point to part_body }
}
state loop { when elapsed > 20 ms -> done }
final done
"""

REACH = """
mission reach
world "bazar/sophia.yaml"

task arms: joint_position(bazar_arms) {
    interpolator = linear(duration = 1 s)
}

state reach {
    enter { enable arms
            arms.target = [0.3, 0, 0, -0.5, 0, 0.5, 0, 0, 0, 0, -0.5, 0, 0.5, 0] rad }
    when arms.reached -> done
}
final done
"""


def robocop(*args):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", *map(str, args)],
                          capture_output=True, text=True, cwd=REPO)


class Stops(Observer):
    """Counts its ``on_stop`` calls and keeps the events."""

    wants_tasks = False

    def __init__(self):
        self.stops, self.events = 0, []

    def on_event(self, event):
        self.events.append(event)

    def on_stop(self, result):
        self.stops += 1


def test_an_action_that_raises_is_a_located_fault_exit_3(tmp_path):
    path = write(tmp_path, "cycle.mission", CYCLE)
    done = robocop("run", path, "--log", tmp_path / "log")
    assert done.returncode == 3, done.stderr
    assert "Traceback" not in done.stderr + done.stdout
    assert "outcome: fault  final state: carry" in done.stdout
    assert ("action 1 of 'when elapsed > 20 ms -> loop' in state 'carry': kinematics: "
            "invalid parent 'part_body'") in " ".join(done.stdout.split())
    events = read_events(tmp_path / "log")
    kinds = [e["kind"] for e in events]
    assert kinds[-2:] == ["fault", "end"]
    end = events[-1]
    assert end["outcome"] == "fault" and end["holding"] is True
    assert len(read_timeseries(tmp_path / "log")["time"]) == end["cycle"]


SAME_BLOCK = """
mission same_block
world "bazar/sophia.yaml"

var z: scalar = 0
var x: length = 1 m

state carry {
    when elapsed > 20 ms -> divide {
        attach part_body to bazar_left_hankamp_tool_object_side
        attach drop_point to part_body
    }
}
state divide {
    when elapsed > 20 ms -> done {
        attach part_body to drop_point
        x = x / z
    }
}
final done
"""


def test_a_block_s_actions_meet_the_frames_its_earlier_actions_moved(tmp_path):
    """The second attach of a block sees the first one's frames (it used to fail for
    want of a state); an attach of the next block that closes a cycle is a fault naming
    the body (one in the same block is an error of ``check``); a division by zero is a
    fault that says so. Either way the summary names the state the failing clause
    leaves."""
    done = robocop("run", write(tmp_path, "same.mission", SAME_BLOCK))
    text = " ".join(done.stdout.split())
    assert done.returncode == 3 and "Traceback" not in done.stderr + done.stdout
    assert ("action 1 of 'when elapsed > 20 ms -> done' in state 'divide': kinematics: "
            "invalid parent 'drop_point'") in text
    assert "final state: divide" in text
    path = write(tmp_path, "divide.mission", SAME_BLOCK.replace(
        "        attach part_body to drop_point\n", ""))
    done = robocop("run", path)
    text = " ".join(done.stdout.split())
    assert done.returncode == 3 and "Traceback" not in done.stderr + done.stdout
    assert ("action 1 of 'when elapsed > 20 ms -> done' in state 'divide': division by "
            "zero: the divisor of a '/' is 0") in text
    assert "final state: divide" in text


def test_debug_prints_the_traceback(tmp_path):
    done = robocop("run", write(tmp_path, "cycle.mission", CYCLE), "--debug")
    assert done.returncode == 3
    assert "Traceback (most recent call last)" in done.stderr
    assert "InvalidParameter" in done.stderr


class BrokenInterpolator(LinearInterpolator):
    """A user's interpolator with a bug that shows after 30 steps."""

    steps = 0

    def step(self):
        self.steps += 1
        if self.steps > 30:
            raise ZeroDivisionError("division by zero")
        return super().step()


def test_a_task_that_raises_is_a_fault_naming_the_task(tmp_path):
    runner = load_mission(write(tmp_path, "reach.mission", REACH)).runner()
    runner.controller.task("arms").set_interpolator(BrokenInterpolator(duration=1.0))
    stops = Stops()
    runner.add_observer(stops)
    result = runner.run()
    assert result.outcome == "fault" and result.final_state == "reach"
    assert result.message.startswith("task 'arms' in state 'reach': ZeroDivisionError")
    assert isinstance(runner.error, ZeroDivisionError)
    assert "in step" in runner.fault_traceback()
    assert stops.stops == 1 and stops.events[-1].data["holding"] is True
    assert [e.kind for e in stops.events].count("fault") == 1


class Crashing(Observer):
    """An observer whose ``on_cycle`` raises from cycle 10 on."""

    wants_tasks = False

    def __init__(self):
        self.stopped = False

    def on_cycle(self, record):
        if record.cycle >= 10:
            raise KeyError("missing")

    def on_stop(self, result):
        self.stopped = True


def test_an_observer_that_raises_is_a_fault_and_still_gets_on_stop(tmp_path):
    runner = load_mission(write(tmp_path, "reach.mission", REACH)).runner()
    crashing, stops = Crashing(), Stops()
    runner.add_observer(crashing)
    runner.add_observer(stops)
    result = runner.run()
    assert result.outcome == "fault" and result.cycles > 10
    assert result.message.startswith("observer Crashing.on_cycle in state 'reach': "
                                     "KeyError: 'missing'")
    assert crashing.stopped and stops.stops == 1


class FlakyDriver:
    """A user's driver that integrates the command and whose ``write`` raises a plain
    Python error on its 20th call."""

    realtime = False

    def __init__(self, world, group):
        self.model, self.group = world.model, world.joint_group(group)
        self.q = world.initial_configuration()
        self.writes, self.holds, self.disconnected = 0, 0, False

    def connect(self):
        pass

    def read(self):
        return self.q.copy(), np.zeros(self.model.nv)

    def write(self, velocity):
        self.writes += 1
        if self.writes == 20:
            raise BrokenPipeError("the robot's bus went away")

    def hold(self):
        self.holds += 1

    def disconnect(self):
        self.disconnected = True


def test_a_driver_that_raises_is_a_fault(tmp_path, bazar):
    mission = load_mission(write(tmp_path, "reach.mission", REACH))
    driver = FlakyDriver(bazar, "bazar_upper_joints")
    runner = mission.runner(driver=driver)
    stops = Stops()
    runner.add_observer(stops)
    result = runner.run()
    assert result.outcome == "fault" and result.cycles == 21   # found in the next cycle
    assert "driver: BrokenPipeError: the robot's bus went away" in result.message
    assert isinstance(runner.error, BrokenPipeError)
    assert driver.disconnected and stops.stops == 1
