"""The driver's state is checked every cycle: a mission run against a robot that reports
a state it cannot be in ends with a fault (exit code 3) naming the joint, the value and
the limit, and the log has the fault event. The robot is the bundled simulator, served
in a thread, whose STATE frames are rewritten once the mission has sent it commands."""

import math
import socket
import threading
from pathlib import Path

import numpy as np
import pytest

from robocop_dsl.cli.main import main
from robocop_dsl.diagnostics import DiagnosticError
from robocop_dsl.drivers import protocol
from robocop_dsl.drivers.simulator import RobotSimulator
from robocop_dsl.runtime import read_events, read_timeseries
from robocop_dsl.safety import RobotStateCheck
from robocop_dsl.world import load_world

REPO = Path(__file__).resolve().parent.parent
GROUP = "panda_arm"
ELBOW = 3
"""``panda_joint4``: URDF limits [-3.0718, -0.0698] rad, 2.175 rad/s."""
COMMANDS = 25
"""Commands the robot receives from the mission before it reports the bad state."""


class TamperedConnection(protocol.Connection):
    """The robot's side of a connection whose STATE frames, once ``after`` commands
    arrived, carry ``tamper(position, velocity, sequence, first)``: ``first`` is the
    sequence number of the first frame rewritten."""

    def __init__(self, sock, hello: protocol.Hello, tamper, after: int):
        super().__init__(sock)
        self.hello, self.tamper, self.after = hello, tamper, after
        self.commands, self.first = 0, None

    def poll(self) -> list:
        messages = super().poll()
        self.commands += sum(m.kind == protocol.COMMAND for m in messages)
        return messages

    def send(self, kind, sequence, time, payload) -> None:
        if kind == protocol.STATE and self.commands >= self.after:
            self.first = sequence if self.first is None else self.first
            position, velocity, holding = protocol.decode_state(
                protocol.Message(kind, sequence, time, payload), self.hello.nq, self.hello.nv)
            position, velocity, sequence = self.tamper(position.copy(), velocity.copy(),
                                                       sequence, self.first)
            payload = protocol.state_payload(position, velocity, holding)
        super().send(kind, sequence, time, payload)


class FakeRobot:
    """The robot simulator for one driver on a free port of 127.0.0.1, in a thread."""

    def __init__(self, world, tamper):
        self.server = socket.create_server((protocol.HOST, 0))
        self.port = self.server.getsockname()[1]
        self.simulator = RobotSimulator(world, GROUP)
        self.connected = threading.Event()
        self.thread = threading.Thread(target=self._serve, args=(tamper,), daemon=True)
        self.thread.start()

    def _serve(self, tamper) -> None:
        client, _ = self.server.accept()
        self.connected.set()
        connection = TamperedConnection(client, self.simulator.hello(), tamper, COMMANDS)
        self.simulator.serve_driver(connection, log=lambda text: None)
        client.close()

    def close(self) -> None:
        """Wait for the robot to lose its driver (connecting once when no driver did)."""
        if not self.connected.is_set():
            socket.create_connection((protocol.HOST, self.port)).close()
        self.thread.join()
        self.server.close()


STATE_TIMEOUT = "5s"
"""Long enough for a robot thread starved by a loaded machine: the checks under test
fault at once, whatever the timeout."""


def mission_on(tmp_path, port: int, controller_options: str = "",
               handled: bool = False) -> Path:
    """missions/panda_reach.mission on the Panda world, its driver the loopback one on
    ``port`` (:data:`STATE_TIMEOUT`); ``controller_options`` are added to its qp_controller's. Unless
    ``handled``, without its ``when controller.failed -> failed`` clause: a fault is
    then the run's outcome."""
    world = (REPO / "robots/panda/panda_on_table.yaml").read_text()
    driver = "type: simulated\n    options: {joint_group: panda_arm}"
    controller = "hierarchy: strict}"
    assert driver in world and controller in world
    world = world.replace(driver, "type: loopback\n    options: {joint_group: panda_arm, "
                                  f"port: {port}, state_timeout: {STATE_TIMEOUT}}}")
    world = world.replace(controller, f"hierarchy: strict{controller_options}}}")
    (tmp_path / "panda_loopback.yaml").write_text(world)
    mission = (REPO / "missions/panda_reach.mission").read_text()
    named, clause = 'world "panda/panda_on_table.yaml"', "when controller.failed -> failed\n"
    assert named in mission and clause in mission
    if not handled:
        mission = mission.replace(clause, "")
    path = tmp_path / "panda_reach.mission"
    path.write_text(mission.replace(named, 'world "panda_loopback.yaml"'))
    return path


def run_against(tmp_path, panda, tamper, *options, controller_options: str = "",
                handled: bool = False):
    """Run the mission against a robot that reports ``tamper``'s states; return the
    exit code and the logged events."""
    robot = FakeRobot(panda, tamper)
    try:
        mission = mission_on(tmp_path, robot.port, controller_options, handled)
        code = main(["run", str(mission), "--log", str(tmp_path / "log"), *options])
    finally:
        robot.close()
    return code, read_events(tmp_path / "log")


def faulted(code: int, events: list, *words: str) -> None:
    """Check exit code 3, one fault event that names ``words``, and the outcome
    ``fault`` with the same message."""
    assert code == 3
    [fault] = [e for e in events if e["kind"] == "fault"]
    message = fault["message"]
    assert all(word in message for word in words), message
    assert events[-1]["outcome"] == "fault" and events[-1]["message"].startswith(message)


def with_position(joint: int, value: float):
    """A tamper that reports ``joint`` at ``value`` [rad]."""
    def tamper(position, velocity, sequence, first):
        position[joint] = value
        return position, velocity, sequence
    return tamper


def with_velocity(joint: int, value: float):
    """A tamper that reports ``joint`` moving at ``value`` [rad/s]."""
    def tamper(position, velocity, sequence, first):
        velocity[joint] = value
        return position, velocity, sequence
    return tamper


def test_a_non_finite_position_is_a_fault(tmp_path, panda):
    """A NaN position faults the run, naming the joint."""
    code, events = run_against(tmp_path, panda, with_position(ELBOW, math.nan))
    faulted(code, events, "panda_joint4", "non-finite position (nan)")


def test_a_non_finite_velocity_is_a_fault(tmp_path, panda):
    """An infinite velocity faults the run, naming the joint."""
    code, events = run_against(tmp_path, panda, with_velocity(ELBOW, math.inf))
    faulted(code, events, "panda_joint4", "non-finite velocity (inf)")


def test_a_joint_past_its_limit_is_a_fault(tmp_path, panda):
    """A joint 0.9 rad past its URDF upper limit faults the run, naming the joint, its
    value, the limit and the tolerance."""
    code, events = run_against(tmp_path, panda, with_position(ELBOW, -0.0698 + 0.9))
    faulted(code, events, "joint 'panda_joint4' at 0.8302 rad",
            "upper limit -0.0698 rad by 0.9 rad", "state_tolerance 0.05 rad")


def test_a_velocity_above_the_urdf_limit_is_a_fault(tmp_path, panda):
    """A velocity of 1e300 rad/s faults the run, naming the joint and its URDF limit."""
    code, events = run_against(tmp_path, panda, with_velocity(ELBOW, 1e300))
    faulted(code, events, "joint 'panda_joint4' moving at 1e+300 rad/s",
            "above 1.5 times its URDF velocity limit 2.175 rad/s")


def test_a_frozen_sequence_number_is_a_fault(tmp_path, panda):
    """A state that jumps 0.5 rad under the sequence number of the state before it is a
    driver fault: the jump never reaches the controller."""
    def frozen(position, velocity, sequence, first):
        position[ELBOW] += 0.5
        return position, velocity, first - 1

    code, events = run_against(tmp_path, panda, frozen)
    faulted(code, events, "broke the protocol", "does not advance past")
    elbow = read_timeseries(tmp_path / "log")["q.panda_joint4"]
    assert np.abs(np.diff(elbow)).max() < 0.1


def test_a_mission_that_handles_failures_takes_its_failure_path(tmp_path, panda):
    """The shipped mission, with its ``when controller.failed -> failed``, handles the
    fault as it does a lost robot: outcome failure (exit code 1), the fault logged."""
    code, events = run_against(tmp_path, panda, with_velocity(ELBOW, 1e300), handled=True)
    assert code == 1
    [fault] = [e for e in events if e["kind"] == "fault"]
    assert "joint 'panda_joint4' moving at 1e+300 rad/s" in fault["message"]
    assert [e["to"] for e in events if e["kind"] == "transition"][-1] == "failed"
    assert events[-1]["outcome"] == "failure"


def test_a_state_within_the_tolerance_runs(tmp_path, panda):
    """A joint reported 0.04 rad past its limit, within the default 0.05 rad, is no
    fault: the controller gets the state (logged) and the run goes on."""
    code, events = run_against(tmp_path, panda, with_position(ELBOW, -0.0698 + 0.04),
                               "--duration", "0.5", handled=True)
    assert code != 3 and not [e for e in events if e["kind"] == "fault"]
    assert events[-1]["outcome"] != "fault"
    elbow = read_timeseries(tmp_path / "log")["q.panda_joint4"]
    assert elbow.max() == pytest.approx(-0.0698 + 0.04)


def test_the_world_sets_the_tolerance(tmp_path, panda):
    """``state_tolerance: 0.01`` in the qp_controller's options makes the same state a
    fault that says so."""
    code, events = run_against(tmp_path, panda, with_position(ELBOW, -0.0698 + 0.04),
                               controller_options=", state_tolerance: 0.01")
    faulted(code, events, "panda_joint4", "upper limit -0.0698 rad",
            "state_tolerance 0.01 rad")


def test_prismatic_joints_get_a_tenth_in_metres(panda):
    """A finger (limits [0, 0.04] m) 4 mm past its limit passes, 6 mm past fails."""
    check = RobotStateCheck(panda, "panda_gripper", 0.05)
    finger = panda.joint_group("panda_gripper").q_indices[0]
    q, v = panda.initial_configuration(), np.zeros(panda.model.nv)
    q[finger] = 0.044
    assert check.check(q, v) is None
    q[finger] = 0.046
    assert "state_tolerance 0.005 m" in check.check(q, v)


def test_continuous_joints_have_no_position_check():
    """A continuous joint of the Jaco at any angle passes; its limited neighbour does
    not."""
    jaco = load_world("kinova/jaco.yaml")
    group = jaco.joint_group("jaco_arm")
    check = RobotStateCheck(jaco, "jaco_arm")
    q, v = jaco.initial_configuration(), np.zeros(jaco.model.nv)
    q[group.q_indices[:2]] = [math.cos(3.0), math.sin(3.0)]
    assert check.check(q, v) is None
    q[group.q_indices[2]] = 10.0
    assert "j2s6s200_joint_2" in check.check(q, v)


@pytest.mark.parametrize("value", ["-0.1", "nan", "fast"])
def test_a_bad_state_tolerance_is_refused(tmp_path, value):
    """``state_tolerance`` must be a number >= 0, checked when the world loads."""
    path = mission_on(tmp_path, 1, f", state_tolerance: {value}").parent
    with pytest.raises(DiagnosticError, match="'state_tolerance' must be a number >= 0"):
        load_world(path / "panda_loopback.yaml")


def test_world_shows_the_tolerance(tmp_path, capsys):
    """``robocop-mission world`` lists ``state_tolerance`` with the controller's options."""
    path = mission_on(tmp_path, 1, ", state_tolerance: 0.1").parent
    assert main(["world", str(path / "panda_loopback.yaml")]) == 0
    assert "state_tolerance: 0.1}" in capsys.readouterr().out
