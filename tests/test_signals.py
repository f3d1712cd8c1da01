"""Signals end a run cleanly: SIGTERM (exit 143), SIGINT once, twice or during
start-up (exit 130). The robot is brought to rest and holds, the summary is printed,
the log is complete (``end`` event, one time series row per cycle), no traceback.
Each test waits for a condition (a file's content, a handler installed), never for
the clock."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from robocop_dsl.runtime import read_events, read_timeseries

REPO = Path(__file__).resolve().parent.parent


def start_run(log: Path) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "robocop_dsl", "run", "missions/pickup.mission", "--realtime",
         "--log", str(log)], cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True)


def wait_for(condition, process: subprocess.Popen) -> None:
    """Poll ``condition()`` until true; fail if the run exits first."""
    while not condition():
        assert process.poll() is None, process.communicate()
        time.sleep(0.02)


def moving(log: Path):
    """True once the run has taken its first transition (the arms are moving)."""
    events = log / "events.jsonl"
    return lambda: events.exists() and '"transition"' in events.read_text()


def handlers_installed(process: subprocess.Popen):
    """True once the process catches SIGTERM: ``run`` has installed its handlers."""
    status = Path(f"/proc/{process.pid}/status")

    def caught() -> bool:
        fields = dict(line.split(":", 1) for line in status.read_text().splitlines())
        return bool(int(fields["SigCgt"], 16) & (1 << (signal.SIGTERM - 1)))
    return caught


def assert_clean_end(process: subprocess.Popen, log: Path, code: int, name: str) -> None:
    out, err = process.communicate()
    assert process.returncode == code, err
    assert "Traceback" not in out + err
    assert "outcome: interrupted" in out and f"interrupted by {name}" in out
    events = read_events(log)
    end = events[-1]
    assert end["kind"] == "end" and end["outcome"] == "interrupted"
    assert end["holding"] is True
    data = read_timeseries(log)
    dropped = [e for e in events if e["kind"] == "dropped"]
    # a real-time log drops cycles rather than hold the loop up (a loaded machine), and
    # says which: every cycle is in the time series or in a dropped event
    assert len(data["time"]) + sum(e["cycles"] for e in dropped) == end["cycle"]
    steps = np.diff(data["time"])
    gaps = np.flatnonzero(~np.isclose(steps, 0.005))
    assert len(gaps) <= len(dropped) and (steps[gaps] > 0.005).all()
    last = gaps[-1] + 1 if len(gaps) else 0      # the last run of cycles: the stop
    commands = np.vstack([data[c][last:] for c in data if c.startswith("command.")]).T
    first = np.zeros((1, commands.shape[1])) if not last else commands[:1]
    sent = np.vstack([first, commands])
    assert not sent[-1].any()
    assert np.abs(np.diff(sent, axis=0)).max() <= 5 * 0.005 + 1e-9   # 5 rad/s^2


def test_sigterm_ends_the_run_cleanly(tmp_path):
    log = tmp_path / "log"
    process = start_run(log)
    wait_for(moving(log), process)
    process.send_signal(signal.SIGTERM)
    assert_clean_end(process, log, 143, "SIGTERM")


def test_sigint_twice_ends_the_run_cleanly(tmp_path):
    log = tmp_path / "log"
    process = start_run(log)
    wait_for(moving(log), process)
    process.send_signal(signal.SIGINT)
    process.send_signal(signal.SIGINT)
    assert_clean_end(process, log, 130, "SIGINT")


def test_sigint_during_start_up_ends_the_run_cleanly(tmp_path):
    """The signal comes while the mission is still being loaded (or, on a slow machine,
    later): either way the run stops at its start and the log is complete."""
    log = tmp_path / "log"
    process = start_run(log)
    wait_for(handlers_installed(process), process)
    process.send_signal(signal.SIGINT)
    assert_clean_end(process, log, 130, "SIGINT")


def writing_process(process: subprocess.Popen) -> list:
    """The pids of the log's writing process once it is started (else empty)."""
    children = Path(f"/proc/{process.pid}/task/{process.pid}/children")
    return [int(pid) for pid in children.read_text().split()] if children.exists() else []


def test_signals_to_every_process_during_start_up_end_the_run_cleanly(tmp_path):
    """A terminal's Ctrl-C goes to the run's whole process group, and a service
    manager's SIGTERM to every process of the service: sent while the log's writing
    process is still starting, the run still stops at its start with a complete log."""
    log = tmp_path / "log"
    process = subprocess.Popen(
        [sys.executable, "-m", "robocop_dsl", "run", "missions/pickup.mission", "--realtime",
         "--log", str(log)], cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True, start_new_session=True)
    wait_for(lambda: writing_process(process), process)
    for pid in writing_process(process):
        os.kill(pid, signal.SIGTERM)
        os.kill(pid, signal.SIGINT)
    os.killpg(process.pid, signal.SIGINT)
    assert_clean_end(process, log, 130, "SIGINT")
