"""The threaded simulated driver and the ThreadedDriver life cycle."""

import math
import textwrap
import threading
import time

import numpy as np
import pytest

from robocop_dsl.diagnostics import RobocopError
from robocop_dsl.drivers import (DriverFault, ThreadedDriver, ThreadedSimulatedDriver,
                                 ThreadOwnershipError)
from robocop_dsl.world import load_world

from driver_loops import MAX_POLLS, control, read_until

GROUP = "bazar_upper_joints"


@pytest.fixture(scope="module")
def wheel_world(tmp_path_factory):
    """A continuous joint (two coordinates, one dof) and a prismatic one."""
    path = tmp_path_factory.mktemp("worlds") / "wheel.yaml"
    path.write_text(textwrap.dedent("""
        models:
          - path: robocop/body.urdf
            namespace: wheel
            joint: {type: continuous, axis: [0, 0, 1]}
          - path: robocop/body.urdf
            namespace: slider
            joint: {type: prismatic, axis: [1, 0, 0],
                    limits: {lower: -10, upper: 10, velocity: 1}}
        joint_groups:
          both: [world_to_wheel_body, world_to_slider_body]
    """))
    return load_world(path)


def test_life_cycle(bazar):
    """read() needs connect(); the robot keeps its configuration across connections."""
    driver = ThreadedSimulatedDriver(bazar, GROUP)
    with pytest.raises(DriverFault, match="not connected"):
        driver.read()
    with driver:
        q, v = driver.read()
        np.testing.assert_array_equal(q, bazar.initial_configuration())
        assert v.shape == (bazar.model.nv,) and not v.any()
        assert driver.last_state.holding, "no command yet: the robot holds"
        control(driver, np.full(16, 0.2), 20)
        moved, _ = driver.read()
    assert not driver.connected
    with pytest.raises(DriverFault):
        driver.write(np.zeros(16))
    with driver:
        again, _ = driver.read()
    assert np.abs(moved - bazar.initial_configuration()).max() > 0
    np.testing.assert_allclose(again, moved, atol=0.2 * 0.06)


def test_position_integrates_the_command_over_the_state_times(bazar):
    """Between two states, q moved by exactly velocity x the time between their stamps."""
    velocity = np.linspace(-0.3, 0.3, 16)
    with ThreadedSimulatedDriver(bazar, GROUP, command_timeout=1.0) as driver:
        control(driver, velocity, 10)
        q_a, v_a = driver.read()
        a = driver.last_state
        control(driver, velocity, 40)
        q_b, _ = driver.read()
        b = driver.last_state
    group = driver.group
    assert not a.holding and not b.holding
    np.testing.assert_allclose(v_a[group.v_indices], velocity)
    np.testing.assert_allclose(q_b[group.q_indices] - q_a[group.q_indices],
                               velocity * (b.time - a.time), atol=1e-9)
    assert b.sequence - a.sequence > 40


def test_continuous_joint_integrates_on_the_circle(wheel_world):
    """A continuous joint's (cos, sin) turns by velocity x time and stays on the circle."""
    velocity = np.array([2.0, 0.1])
    with ThreadedSimulatedDriver(wheel_world, "both", command_timeout=1.0) as driver:
        control(driver, velocity, 10)
        q_a, _ = driver.read()
        a = driver.last_state
        control(driver, velocity, 60)
        q_b, _ = driver.read()
        b = driver.last_state
    group = wheel_world.joint_group("both")
    cos_a, sin_a, x_a = q_a[group.q_indices]
    cos_b, sin_b, x_b = q_b[group.q_indices]
    assert math.hypot(cos_b, sin_b) == pytest.approx(1.0, abs=1e-12)
    turned = math.atan2(sin_b, cos_b) - math.atan2(sin_a, cos_a)
    expected = 2.0 * (b.time - a.time)
    assert math.remainder(turned - expected, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
    assert x_b - x_a == pytest.approx(0.1 * (b.time - a.time), abs=1e-12)


def test_command_timeout_holds_the_robot(bazar):
    """A command older than the timeout makes the robot hold: zero velocity, q still."""
    with ThreadedSimulatedDriver(bazar, GROUP, command_timeout=0.03) as driver:
        start, _ = driver.read()
        driver.write(np.full(16, 0.5))
        read_until(driver, lambda state: not state.holding)
        held = read_until(driver, lambda state: state.holding)
        sequence = driver.last_state.sequence
        later = read_until(driver, lambda state: state.sequence > sequence + 50)
        _, v = driver.read()
    assert np.abs(held - start).max() > 0, "the command moved the robot first"
    np.testing.assert_array_equal(later, held)
    assert not v.any()


def test_rate_is_kept(bazar):
    """The driver keeps to its period: every tick between two states was either served
    (a state published) or counted as missed (a loaded machine makes it late, never
    slower); a few ticks may pass between reading a state and the count."""
    with ThreadedSimulatedDriver(bazar, GROUP, period=0.002) as driver:
        driver.read()
        a, missed_a = driver.last_state, driver.missed
        control(driver, np.zeros(16), 100)
        driver.read()
        b, missed_b = driver.last_state, driver.missed
    ticks = (b.time - a.time) / 0.002
    assert b.sequence - a.sequence > 0
    assert abs(b.sequence - a.sequence + missed_b - missed_a - ticks) <= 5
    assert "500 Hz" in repr(driver)


class StallingDriver(ThreadedDriver):
    """Publishes one state, then its thread blocks until released."""

    def __init__(self, world, **kwargs):
        super().__init__(world, GROUP, **kwargs)
        self.release = threading.Event()
        self.commands = []

    def _serve(self):
        self._publish(self.initial[self.group.q_indices], np.zeros(16), True, time.monotonic())
        self.release.wait()
        self.commands.append(self.reader.sync())


def test_controller_never_waits_for_a_stalled_driver_thread(bazar):
    """read()/write() only copy: they go on while the driver thread is stuck, and
    read() reports the stale state as a fault once it is older than state_timeout."""
    driver = StallingDriver(bazar, state_timeout=0.05)
    driver.connect()
    for k in range(500):
        driver.write(np.full(16, float(k)))
    with pytest.raises(DriverFault, match="no state from the robot for"):
        for _ in range(MAX_POLLS):
            driver.read()
            time.sleep(0.002)
    driver.release.set()
    driver.disconnect()
    assert driver.commands[0].sequence == 500 and np.all(driver.commands[0].velocity == 499)


class CrashingDriver(ThreadedDriver):
    """Its thread fails after publishing one state."""

    def __init__(self, world, **kwargs):
        super().__init__(world, GROUP, **kwargs)
        self.crash = threading.Event()

    def _serve(self):
        self._publish(self.initial[self.group.q_indices], np.zeros(16), True, time.monotonic())
        self.crash.wait()
        raise RuntimeError("encoder failure")


def test_a_failing_driver_thread_is_a_driver_fault(bazar):
    """The exception that ends the driver thread reaches read() and write()."""
    driver = CrashingDriver(bazar)
    driver.connect()
    driver.read()
    driver.crash.set()
    with pytest.raises(DriverFault):
        for _ in range(MAX_POLLS):
            driver.read()
            time.sleep(0.002)
    for call in (driver.read, lambda: driver.write(np.zeros(16))):
        with pytest.raises(DriverFault, match="driver thread stopped: RuntimeError: "
                                              "encoder failure") as caught:
            call()
        assert isinstance(caught.value, RobocopError)
    driver.disconnect()


class SilentDriver(ThreadedDriver):
    """Never publishes a state."""

    def _serve(self):
        self._stop.wait()


def test_connect_fails_when_no_state_comes(bazar):
    """connect() gives up after connect_timeout and leaves the driver disconnected."""
    driver = SilentDriver(bazar, GROUP, connect_timeout=0.05)
    with pytest.raises(DriverFault, match="no state within 0.05 s"):
        driver.connect()
    assert not driver.connected


def test_read_belongs_to_the_controller_thread(bazar):
    """After the controller thread read once, another thread's read() is refused."""
    with ThreadedSimulatedDriver(bazar, GROUP) as driver:
        driver.read()
        errors = []

        def other():
            try:
                driver.read()
            except ThreadOwnershipError as error:
                errors.append(error)

        thread = threading.Thread(target=other, name="viewer")
        thread.start()
        thread.join()
    assert len(errors) == 1 and "thread 'viewer'" in str(errors[0])
