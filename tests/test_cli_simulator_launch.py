"""``python -m robocop_dsl.drivers.simulator`` starts without Python warnings, and a
simulator that does not start is reported with its own last words."""

import socket
import subprocess
import sys

import pytest

from robocop_dsl.drivers import DriverFault, LoopbackDriver, SimulatorProcess

GROUP = "bazar_upper_joints"


def test_the_module_runs_without_a_runpy_warning(bazar):
    """Warnings are errors here: a package that imported the module first would make
    runpy warn, and the warning would turn into a traceback and exit code 1."""
    done = subprocess.run([sys.executable, "-W", "error", "-m", "robocop_dsl.drivers.simulator",
                           "--port", "0", "--world", str(bazar.path), "--joint-group",
                           "bazar_tail"], capture_output=True, text=True, check=False)
    assert done.returncode == 2, done.stderr
    assert "Warning" not in done.stderr
    assert "has no joint group or joint 'bazar_tail'" in done.stderr


def test_a_launched_simulator_prints_no_warning(bazar):
    """The simulator the loopback driver launches starts, serves and leaves stderr empty."""
    process = SimulatorProcess(bazar.path, GROUP)
    process.args[1:1] = ["-W", "error"]
    with process:
        with LoopbackDriver(bazar, GROUP, port=process.port) as driver:
            q, _ = driver.read()
            assert q.shape == (16,)
        child = process.process
        process.stop()
    assert child.returncode is not None


def test_did_not_start_names_the_real_cause(bazar):
    """An unknown group: the simulator's own message, not a warning, is the cause."""
    with pytest.raises(DriverFault) as caught:
        SimulatorProcess(bazar.path, "bazar_tail").start()
    message = str(caught.value)
    assert "did not start (exit code 2)" in message
    assert "has no joint group or joint 'bazar_tail'" in message
    assert "RuntimeWarning" not in message


def test_a_crash_quotes_the_last_lines_of_the_traceback(bazar):
    """A port already taken: the simulator dies with a traceback; the report quotes its
    last lines (the exception), not its first."""
    with socket.create_server(("127.0.0.1", 0)) as taken:
        port = taken.getsockname()[1]
        process = SimulatorProcess(bazar.path, GROUP, port=port)
        with pytest.raises(DriverFault) as caught:
            process.start()
        process.stop()
    message = str(caught.value)
    assert "Address already in use" in message
    assert "Traceback" not in message
    assert len(message.splitlines()) <= 5
