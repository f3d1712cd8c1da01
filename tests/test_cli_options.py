"""The command line's own options, called as a user calls them: ``--version``, ``--help``
without the heavy libraries, a closed output pipe, ``run --event NAME@TIME``."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

import robocop_dsl

REPO = Path(__file__).resolve().parent.parent
COMMANDS = ("check", "run", "graph", "world", "plot", "sweep")
HEAVY = ("pinocchio", "networkx", "matplotlib", "meshcat", "dask", "pyarrow", "lark",
         "proxsuite", "ruckig", "numpy")

EVENTS = '''mission m
world "bazar/sophia.yaml"
event go "the operator says go"
event stop "the operator says stop"
state wait {
    when event go -> armed
    when elapsed > 2 s -> failed
}
state armed {
    when event stop -> done
    when elapsed > 2 s -> failed
}
final done
final failed: failure
'''


def robocop(*args, **kwargs):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", *map(str, args)],
                          capture_output=True, text=True, cwd=REPO, check=False, **kwargs)


def test_version():
    done = robocop("--version")
    assert done.returncode == 0
    assert done.stdout.strip() == f"robocop-mission {robocop_dsl.__version__}"


def _modules_loaded(*arguments) -> tuple[int, set]:
    """The exit code of ``robocop-mission ARGUMENTS`` and the modules its interpreter
    had loaded when it exited."""
    probe = ("import sys, atexit\n"
             "atexit.register(lambda: sys.__stderr__.write('MODULES ' + ' '.join(sys.modules)))\n"
             "sys.argv = ['robocop-mission', *sys.argv[1:]]\n"
             "from robocop_dsl.cli.main import entry_point\n"
             "entry_point()\n")
    done = subprocess.run([sys.executable, "-c", probe, *arguments], capture_output=True,
                          text=True, cwd=REPO, check=False)
    return done.returncode, set(done.stderr.rsplit("MODULES ", 1)[1].split())


@pytest.mark.parametrize("arguments", [["--help"], ["--version"], []]
                         + [[command, "--help"] for command in COMMANDS])
def test_help_imports_no_heavy_library(arguments):
    """Help and version come from the standard library and the command modules alone:
    the modules loaded are listed by the interpreter that answered."""
    returncode, modules = _modules_loaded(*arguments)
    assert returncode == (2 if not arguments else 0)
    assert "robocop_dsl.cli.main" in modules
    assert not {m for m in HEAVY if m in modules}


def test_check_imports_no_qp_library_for_proxqp():
    """``check`` of a mission whose controller uses ProxQP loads neither qpsolvers nor
    SciPy (a third of its start-up): ProxQP is built in. Nor does it load the compiler
    and its specs: it wants the diagnostics alone."""
    returncode, modules = _modules_loaded("check", "missions/pickup.mission")
    assert returncode == 0
    assert "robocop_dsl.check.checker" in modules
    assert not {m for m in ("qpsolvers", "scipy", "robocop_dsl.compile.compiler",
                            "robocop_dsl.compile.spec") if m in modules}


def test_no_arguments_prints_the_help_as_a_usage_error():
    done = robocop()
    assert done.returncode == 2
    assert "COMMAND" in done.stderr and "--version" in done.stderr
    assert all(command in done.stderr for command in COMMANDS)


def test_a_closed_output_pipe_ends_quietly():
    """The reader is gone before the world is printed: exit 141, nothing on stderr."""
    read, write = os.pipe()
    os.close(read)
    try:
        done = subprocess.run([sys.executable, "-m", "robocop_dsl", "world",
                               "bazar/sophia.yaml"], stdout=write, stderr=subprocess.PIPE,
                              text=True, cwd=REPO, check=False)
    finally:
        os.close(write)
    assert done.returncode == 141
    assert done.stderr == ""


def test_head_reads_the_first_line_of_the_world():
    """``robocop-mission world ... | head -1`` in a shell: one line, no traceback."""
    done = subprocess.run(f"'{sys.executable}' -m robocop_dsl world bazar/sophia.yaml "
                          "--format json | head -1", shell=True, capture_output=True,
                          text=True, cwd=REPO, check=False)
    assert done.stdout == "{\n"
    assert "Traceback" not in done.stderr and "Error" not in done.stderr


def test_events_are_raised_at_their_mission_times(tmp_path):
    """Two events, each raised after the cycle that reaches its time and seen from the
    next cycle: the transitions follow them one cycle (5 ms) later."""
    mission = tmp_path / "events.mission"
    mission.write_text(EVENTS)
    log = tmp_path / "log"
    done = robocop("run", mission, "--event", "go@0.3", "--event", "stop@450ms",
                   "--log", log)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "0.300 s  event: go" in done.stderr and "0.450 s  event: stop" in done.stderr
    from robocop_dsl.runtime import read_events

    events = read_events(log)
    raised = [(e["name"], e["time"]) for e in events if e["kind"] == "event"]
    assert raised == [("go", 0.3), ("stop", 0.45)]
    moves = [(e["to"], e["time"]) for e in events if e["kind"] == "transition"]
    assert moves == [("armed", 0.305), ("done", 0.455)]


def test_without_the_event_the_mission_times_out(tmp_path):
    mission = tmp_path / "events.mission"
    mission.write_text(EVENTS)
    done = robocop("run", mission, "--event", "go@0.1")
    assert done.returncode == 1
    assert "armed -> failed" in done.stdout


@pytest.mark.parametrize("option, message", [
    ("go", "'go' is not NAME@TIME"),
    ("go@soon", "'go@soon' is not NAME@TIME"),
    ("gp@1", "the mission has no event 'gp' (its events: go, stop); did you mean 'go'?"),
])
def test_a_bad_event_is_a_usage_error(tmp_path, option, message):
    mission = tmp_path / "events.mission"
    mission.write_text(EVENTS)
    done = robocop("run", mission, "--event", option)
    assert done.returncode == 2
    assert message in done.stderr
    assert "Traceback" not in done.stderr


@pytest.mark.parametrize("duration, message", [
    ("-1", "-1: a duration is a finite number of seconds above 0"),
    ("0", "0: a duration is a finite number of seconds above 0"),
    ("nan", "nan: a duration is a finite number of seconds above 0"),
    ("soon", "'soon' is not a number of seconds"),
])
def test_a_duration_that_is_not_a_time_ahead_is_a_usage_error(duration, message):
    done = robocop("run", "missions/pickup.mission", f"--duration={duration}")
    assert done.returncode == 2 and message in done.stderr
    assert "Traceback" not in done.stderr
