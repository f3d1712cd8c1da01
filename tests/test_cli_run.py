"""``robocop-mission run`` as a user calls it: exit codes, summary, log, Ctrl-C."""

import re
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np

from robocop_dsl.runtime import read_events, read_timeseries

from test_signals import assert_clean_end, moving, start_run, wait_for

REPO = Path(__file__).resolve().parent.parent


def robocop(*args, **kwargs):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", *map(str, args)],
                          capture_output=True, text=True, cwd=REPO, **kwargs)


def write(tmp_path, body):
    path = tmp_path / "m.mission"
    path.write_text('mission m\nworld "bazar/sophia.yaml"\n' + body)
    return path


def test_pickup_succeeds_with_the_seed_sequence(tmp_path):
    done = robocop("run", "missions/pickup.mission", "--log", tmp_path / "log")
    assert done.returncode == 0, done.stderr
    assert "leaked" not in done.stderr  # every binding's object is released at exit
    out = done.stdout
    assert "outcome: success  final state: done" in out
    rows = [[cell.strip() for cell in line.split("│")] for line in out.splitlines()
            if line.count("│") == 3]
    steps = ["approach", "grasp", "lift", "move_to_drop", "release"]
    assert [(row[1], row[2]) for row in rows if "/" not in row[1]] == [
        ("goto_initial_pose", "approach"), ("approach", "grasp"), ("grasp", "lift"),
        ("lift", "move_to_drop"), ("move_to_drop", "release"), ("release", "return"),
        ("return", "done")]
    assert [(row[1], row[2]) for row in rows if "/" in row[1]] == [
        (f"{step}/moving", f"{step}/there") for step in steps]
    assert "QP failures: 0" in out
    transitions = [e for e in read_events(tmp_path / "log") if e["kind"] == "transition"]
    assert [e["to"] for e in transitions if "/" not in e["to"]] == [
        "approach", "grasp", "lift", "move_to_drop", "release", "return", "done"]
    data = read_timeseries(tmp_path / "log")
    end = [e for e in read_events(tmp_path / "log") if e["kind"] == "end"][0]
    assert end["outcome"] == "success"
    assert len(data["time"]) == end["cycle"]
    assert set(data["state"]) == {"goto_initial_pose", "return", "done",
                                  *(f"{step}/{leaf}" for step in steps
                                    for leaf in ("moving", "there"))}
    assert "error.left_tool" in data and "reference.left_tool.5" in data
    assert "q.bazar_left_joint_1" in data and "command.bazar_ptu_joint_tilt" in data
    grasp = data["state"] == "grasp/moving"
    assert np.nanmin(data["error.left_tool"][grasp]) < 1e-3
    assert data["solved"].all()


def test_a_composed_mission_reports_configurations_and_full_paths(tmp_path):
    """The progress, the summary's transitions, the log's events and ``state`` column
    show full paths and the configuration of both regions."""
    path = write(tmp_path, """
state both: parallel {
    region left {
        state first { when elapsed >= 10 ms -> arrived }
        final arrived
    }
    region right {
        state first { when elapsed >= 20 ms -> arrived }
        final arrived
    }
    when both.done -> finish
}
final finish
""")
    done = robocop("run", path, "--log", tmp_path / "log", "--duration", "1")
    assert done.returncode == 0, done.stderr
    assert "start in both/left/first | both/right/first" in done.stderr
    assert "both/left/first -> both/left/arrived  (elapsed >= 10 ms)" in done.stderr
    rows = [[cell.strip() for cell in line.split("│")] for line in done.stdout.splitlines()
            if line.count("│") == 3]
    assert [(row[1], row[2]) for row in rows] == [
        ("both/left/first", "both/left/arrived"), ("both/right/first", "both/right/arrived"),
        ("both", "finish")]
    events = read_events(tmp_path / "log")
    assert events[0]["state"] == "both/left/first | both/right/first"
    assert [(e["cycle"], e["from"], e["to"]) for e in events if e["kind"] == "transition"] == [
        (2, "both/left/first", "both/left/arrived"), (4, "both/right/first", "both/right/arrived"),
        (5, "both", "finish")]
    assert list(read_timeseries(tmp_path / "log")["state"]) == [
        "both/left/first | both/right/first"] * 2 + ["both/left/arrived | both/right/first"] * 2 \
        + ["both/left/arrived | both/right/arrived", "finish"]


def test_failure_outcome_exits_1(tmp_path):
    path = write(tmp_path, "state wait { when elapsed > 50 ms -> broken }\nfinal broken: failure\n")
    done = robocop("run", path)
    assert done.returncode == 1
    assert "outcome: failure  final state: broken" in done.stdout


def test_invalid_mission_exits_2(tmp_path):
    path = write(tmp_path, "state wait { when elapsed > 50 ms -> nowhere }\n")
    done = robocop("run", path)
    assert done.returncode == 2
    assert "error[" in done.stderr and "nowhere" in done.stderr
    assert "Traceback" not in done.stderr


def test_unhandled_fault_exits_3_and_keeps_the_log(tmp_path):
    path = write(tmp_path, """
constraint above: joint_kinematic(bazar_left_arm) { min_position = [1, 1, 1, 1, 1, 1, 1] rad }
constraint below: joint_kinematic(bazar_left_arm)
state hold {
    enter { below.max_position = [-1, -1, -1, -1, -1, -1, -1] rad }
    when elapsed > 1 s -> done
}
final done
""")
    done = robocop("run", path, "--log", tmp_path / "log")
    assert done.returncode == 3
    assert "outcome: fault" in done.stdout and "no QP solution" in done.stdout
    kinds = [e["kind"] for e in read_events(tmp_path / "log")]
    assert kinds == ["start", "qp_failure", "end"]
    assert len(read_timeseries(tmp_path / "log")["time"]) == 2


def test_a_target_that_is_not_finite_is_a_fault_that_shows_the_values(tmp_path):
    """A var used before it is assigned makes a target of NaN: the fault says which
    values, as written in a mission (no numpy text)."""
    path = write(tmp_path, """
task tool: body_pose(bazar_left_hankamp_tool_object_side) { reference = world }
var z: length
state hold {
    enter {
        enable tool
        tool.target = pickup_point offset [0, 0, z]
    }
    when elapsed > 1 s -> done
}
final done
""")
    done = robocop("run", path)
    assert done.returncode == 3
    assert "invalid target offset [0.0, 0.0, nan]: expected finite numbers" in \
        " ".join(done.stdout.split())
    assert "array(" not in done.stdout + done.stderr


def test_duration_caps_mission_time():
    done = robocop("run", "missions/pickup.mission", "--duration", "1")
    assert done.returncode == 1
    assert "outcome: stopped  final state: approach" in done.stdout or \
        "outcome: stopped  final state: goto_initial_pose" in done.stdout
    stop = float(re.search(r"mission time: ([0-9.]+) s", done.stdout).group(1))
    assert 1.0 <= stop <= 1.0 + 1 / 5 + 0.005   # 1 rad/s braked at 5 rad/s^2
    assert "duration of 1 s reached; brought to rest in" in done.stdout


def test_solver_override_and_unknown_solver():
    assert robocop("run", "missions/pickup.mission", "--solver", "daqp",
                   "--hierarchy", "weighted").returncode == 0
    done = robocop("run", "missions/pickup.mission", "--solver", "nosuch")
    assert done.returncode == 2
    assert "nosuch" in done.stderr and "proxqp" in done.stderr


def test_ctrl_c_holds_and_keeps_a_complete_log(tmp_path):
    """Ctrl-C once while the arms move: exit 130, the robot held, the log complete."""
    log = tmp_path / "log"
    process = start_run(log)
    wait_for(moving(log), process)
    process.send_signal(signal.SIGINT)
    assert_clean_end(process, log, 130, "SIGINT")


def test_an_unhandled_failure_says_what_failed(tmp_path):
    """A pose task weighted 1e300 leaves the QP solver without an answer within its
    budget; with no clause on ``controller.failed`` the run is a fault whose reason says
    so (it said "run-time fault with no handler")."""
    text = (REPO / "missions" / "pickup.mission").read_text()
    text = text.replace('world "bazar/sophia.yaml"', f'world "{REPO}/robots/bazar/sophia.yaml"')
    text = text.replace("    priority     = 0                       # 0 is highest",
                        "    weight       = 1e300\n    priority     = 0  # 0 is highest")
    text = "\n".join(line for line in text.split("\n") if "controller.failed" not in line)
    path = tmp_path / "heavy.mission"
    path.write_text(text)
    done = robocop("run", path, "--log", tmp_path / "log")
    assert done.returncode == 3 and "outcome: fault" in done.stdout
    events = read_events(tmp_path / "log")
    failed = [e for e in events if e["kind"] in ("solver_budget", "constraint_relaxed")]
    assert failed, [e["kind"] for e in events]
    reason = " ".join(done.stdout.split())
    assert f"reason: the controller failed in state '{failed[0]['state']}': " in reason
    assert "run-time fault with no handler" not in reason
