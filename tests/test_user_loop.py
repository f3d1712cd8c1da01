"""The public loop API: ``start()``, ``step()``, ``emit()``, ``stop()`` and ``finish()``
drive a mission from a loop the user writes, as ``run()`` does."""

import subprocess
import sys
from pathlib import Path

import numpy as np

from robocop_dsl.runtime import Observer, load_mission

REPO = Path(__file__).resolve().parent.parent
EXAMPLE = REPO / "examples" / "user_loop.py"
MISSION = REPO / "examples" / "operator_go.mission"


class Watch(Observer):
    """Counts ``on_start``/``on_stop`` and keeps the commands and events."""

    wants_tasks = False

    def __init__(self):
        self.starts = self.stops = 0
        self.commands, self.events = [], []

    def on_start(self, runner):
        self.starts += 1

    def on_cycle(self, record):
        self.commands.append(record.command.copy())

    def on_event(self, event):
        self.events.append(event)

    def on_stop(self, result):
        self.stops += 1


def test_the_example_drives_the_mission_from_its_own_loop():
    done = subprocess.run([sys.executable, str(EXAMPLE), "--go-at", "0.5"],
                          capture_output=True, text=True, cwd=REPO)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[0] == "start in wait (period 5 ms)"
    assert lines[1] == "  0.500 s  go raised in wait"
    assert lines[2] == "  0.500 s  wait -> reach"
    assert lines[-1].startswith("outcome: success  final state: done")


def test_start_step_emit_finish():
    runner = load_mission(MISSION).runner()
    watch = Watch()
    runner.add_observer(watch)
    runner.start()
    runner.start()
    assert watch.starts == 1 and runner.state == "wait" and runner.cycle == 0
    for _ in range(10):
        assert runner.step()
    runner.emit("go")
    while runner.step():
        assert runner.outcome in (None, "success")
    assert runner.finished and runner.outcome == "success"
    assert not runner.step()
    result = runner.finish()
    assert result is runner.finish() and watch.stops == 1
    assert result.outcome == "success" and result.final_state == "done"
    assert [(t.time, t.source, t.target) for t in result.transitions][0] == (0.05, "wait",
                                                                           "reach")
    assert [e.kind for e in watch.events][-1] == "end"


def test_finish_while_moving_brakes_then_holds():
    """Leaving the loop early: ``finish()`` stops the run (``interrupted``), brings the
    robot to rest within 5 rad/s^2, holds, and tells the observers once."""
    runner = load_mission(MISSION).runner()
    watch = Watch()
    runner.add_observer(watch)
    runner.emit("go")
    while runner.time < 3.0:
        runner.step()
    moving = len(watch.commands)
    assert np.abs(watch.commands[-1]).max() > 0.1
    result = runner.finish()
    assert result.outcome == "interrupted" and result.final_state == "reach"
    assert result.message.startswith("finished before the mission ended; brought to rest")
    sent = np.vstack([np.zeros(16), *watch.commands])
    assert len(watch.commands) > moving + 1 and not sent[-1].any()
    assert np.abs(np.diff(sent, axis=0)).max() <= 5 * 0.005 + 1e-9
    assert watch.events[-1].data["holding"] is True and watch.stops == 1
