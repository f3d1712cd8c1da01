"""The terminal output of a real-time run is printed while the loop sleeps: a blocked
terminal does not hold the loop up, and every line comes out, in order."""

import io
import threading

from robocop_dsl.cli.progress import ProgressDisplay
from robocop_dsl.runtime import load_mission
from robocop_dsl.runtime.records import Event

from conftest import MISSIONS


class Held(io.StringIO):
    """A terminal whose writes of transition lines wait until it is released."""

    def __init__(self):
        super().__init__()
        self.released = threading.Event()
        self.waiting = threading.Event()

    def write(self, text):
        if "->" in text:
            self.waiting.set()
            self.released.wait()
        return super().write(text)

    def isatty(self):
        return False


def test_a_blocked_terminal_does_not_hold_a_real_time_run_up():
    runner = load_mission(MISSIONS / "pickup.mission").runner()
    terminal = Held()
    display = ProgressDisplay("pickup", stream=terminal, realtime=True)
    runner.add_observer(display)
    result = runner.run(duration=3.0, realtime=True)
    assert terminal.waiting.is_set(), "the transition line was not printed during the run"
    assert not terminal.released.is_set()
    assert result.outcome == "stopped"
    assert runner.time >= 3.0
    terminal.released.set()
    display.close()
    lines = terminal.getvalue().splitlines()
    assert lines[0] == "pickup: start in goto_initial_pose"
    assert any("goto_initial_pose -> approach" in line for line in lines)


class Sleeping:
    """A runner seen by the display: real time, never sleeping until it ends."""

    state = "start"
    next_cycle_at = None


def test_every_line_comes_out_in_order_however_many_wait():
    terminal = io.StringIO()
    display = ProgressDisplay("m", stream=terminal, realtime=True)
    display.on_start(Sleeping())
    for index in range(200):
        display.on_event(Event("log", index * 0.01, index, {"message": f"line {index}"}))
    display.close()
    logged = [line.split("log: ")[1] for line in terminal.getvalue().splitlines()[1:]]
    assert logged == [f"line {index}" for index in range(200)]
