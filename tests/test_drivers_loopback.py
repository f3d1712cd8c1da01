"""The loopback driver against the robot simulator running as a separate process."""

import signal
import socket
import subprocess
import sys
import time

import numpy as np
import pytest

from robocop_dsl.drivers import DriverFault, LoopbackDriver, SimulatorProcess

from driver_loops import MAX_POLLS, control, read_until

GROUP = "bazar_upper_joints"


@pytest.fixture
def simulator(bazar):
    """A fresh robot simulator process for the BAZAR upper body."""
    with SimulatorProcess(bazar.path, GROUP, command_timeout=0.05) as process:
        yield process


def test_handshake_and_first_state(bazar, simulator):
    """The robot names its joints and starts at the world's initial configuration."""
    with LoopbackDriver(bazar, GROUP, port=simulator.port) as driver:
        q, v = driver.read()
        assert driver.hello.joints == driver.group.joints
        assert driver.hello.period == pytest.approx(0.001)
    np.testing.assert_allclose(q, bazar.initial_configuration())
    assert not v.any() and driver.last_state.holding


def test_robot_follows_the_commands(bazar, simulator):
    """Displacement over a run matches velocity x time (ratio within 10 %)."""
    velocity = np.linspace(0.1, 0.4, 16)
    with LoopbackDriver(bazar, GROUP, port=simulator.port) as driver:
        control(driver, velocity, 10)
        q_a, _ = driver.read()
        a = driver.last_state
        control(driver, velocity, 60)
        q_b, v_b = driver.read()
        b = driver.last_state
    group = driver.group
    assert not b.holding
    np.testing.assert_allclose(v_b[group.v_indices], velocity)
    ratio = (q_b - q_a)[group.q_indices] / (velocity * (b.time - a.time))
    np.testing.assert_allclose(ratio, 1.0, atol=0.1)


def test_losing_the_robot_mid_run_is_a_driver_fault(bazar, simulator):
    """Killing the simulator makes read()/write() raise DriverFault from then on."""
    driver = LoopbackDriver(bazar, GROUP, port=simulator.port)
    driver.connect()
    faults = []
    for cycle in range(400):
        if cycle == 50:
            simulator.kill()
        try:
            driver.read()
            driver.write(np.full(16, 0.1))
        except DriverFault as fault:
            faults.append((cycle, fault))
        time.sleep(0.005)
    driver.disconnect()
    first = faults[0][0]
    assert first >= 50, "no fault while the robot answered"
    assert [c for c, _ in faults] == list(range(first, 400)), "every later cycle faults"
    assert "connection to the robot at 127.0.0.1" in str(faults[0][1])
    assert "lost" in faults[0][1].reason


def test_a_silent_robot_is_a_driver_fault(bazar, simulator):
    """A robot that stops sending states (process stopped) faults after state_timeout."""
    driver = LoopbackDriver(bazar, GROUP, port=simulator.port, state_timeout=0.1)
    driver.connect()
    driver.read()
    simulator.process.send_signal(signal.SIGSTOP)
    try:
        with pytest.raises(DriverFault, match="no state from the robot"):
            for _ in range(MAX_POLLS):
                driver.read()
                time.sleep(0.002)
    finally:
        simulator.process.send_signal(signal.SIGCONT)
        driver.disconnect()


def test_robot_holds_when_commands_stop(bazar, simulator):
    """The robot's own command timeout holds it when the driver stops writing."""
    with LoopbackDriver(bazar, GROUP, port=simulator.port) as driver:
        driver.read()
        driver.write(np.full(16, 0.3))
        read_until(driver, lambda state: not state.holding)
        held = read_until(driver, lambda state: state.holding)
        sequence = driver.last_state.sequence
        later = read_until(driver, lambda state: state.sequence > sequence + 50)
    np.testing.assert_array_equal(later, held)


def test_robot_holds_and_keeps_its_pose_when_the_driver_leaves(bazar, simulator):
    """After a disconnect the robot stands still where it was; a new driver finds it."""
    with LoopbackDriver(bazar, GROUP, port=simulator.port) as driver:
        control(driver, np.full(16, 0.3), 40)
        left, _ = driver.read()
    with LoopbackDriver(bazar, GROUP, port=simulator.port) as driver:
        found, v = driver.read()
        assert driver.last_state.holding and not v.any()
    assert np.abs(left - bazar.initial_configuration()).max() > 0.01
    np.testing.assert_allclose(found, left, atol=0.3 * 0.02)


def test_robot_with_other_joints_is_refused(bazar):
    """A robot announcing other joints than the group's is refused at connect()."""
    with SimulatorProcess(bazar.path, "bazar_arms") as process:
        driver = LoopbackDriver(bazar, GROUP, port=process.port)
        with pytest.raises(DriverFault, match="the robot drives"):
            driver.connect()
        assert not driver.connected


def test_nobody_listening(bazar):
    """connect() to a port with no robot is a DriverFault naming the problem."""
    with socket.create_server(("127.0.0.1", 0)) as probe:
        port = probe.getsockname()[1]
    with pytest.raises(DriverFault, match="cannot reach the robot"):
        LoopbackDriver(bazar, GROUP, port=port).connect()


def test_launch_starts_and_stops_the_simulator(bazar):
    """With launch=True the driver owns a simulator process for its connection."""
    driver = LoopbackDriver(bazar, GROUP, launch=True)
    with driver:
        process = driver.simulator.process
        control(driver, np.zeros(16), 3)
        assert driver.port > 0
    assert driver.simulator is None and process.poll() is not None


def test_simulator_rejects_an_unknown_group(bazar):
    """The simulator command exits with 2 and says which group it could not find."""
    result = subprocess.run([sys.executable, "-m", "robocop_dsl.drivers.simulator",
                             "--port", "0", "--world", str(bazar.path),
                             "--joint-group", "bazar_tail"],
                            capture_output=True, text=True, check=False)
    assert result.returncode == 2
    assert "has no joint group or joint 'bazar_tail'" in result.stderr
