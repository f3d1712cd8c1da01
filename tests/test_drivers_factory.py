"""Building a world's driver from its processors, and the rate/period options."""

import textwrap

import pytest

from robocop_dsl.diagnostics import DiagnosticError
from robocop_dsl.drivers import (DriverConfigError, LoopbackDriver, ThreadedSimulatedDriver,
                                 create_driver)
from robocop_dsl.drivers.timing import Ticker, parse_rate, period_from_options
from robocop_dsl.runtime.driver import SimulatedDriver
from robocop_dsl.world import load_world


def world_with(tmp_path, processors: str):
    """The BAZAR work cell with the given ``processors:`` block."""
    path = tmp_path / "w.yaml"
    path.write_text("models:\n  - include: bazar/workcell.yaml\nprocessors:\n"
                    + textwrap.indent(textwrap.dedent(processors).strip("\n"), "  ") + "\n")
    return load_world(path)


@pytest.mark.parametrize("options, period", [
    ({}, 0.001),
    ({"rate": "1kHz"}, 0.001),
    ({"rate": "250 Hz"}, 0.004),
    ({"rate": 500}, 0.002),
    ({"period": 0.002}, 0.002),
    ({"period": "2ms"}, 0.002),
])
def test_rate_or_period(options, period):
    """Either ``rate`` or ``period`` sets the driver thread's period."""
    assert period_from_options(options, 0.001) == pytest.approx(period)


@pytest.mark.parametrize("options, message", [
    ({"rate": "1kHz", "period": 0.001}, "either 'rate' or 'period'"),
    ({"rate": "fast"}, "not a rate"),
    ({"rate": "0Hz"}, "must be positive"),
    ({"period": "1 minute"}, "not a duration"),
])
def test_bad_rate_or_period(options, message):
    """Conflicting or malformed rates are refused with a clear message."""
    with pytest.raises(DriverConfigError, match=message):
        period_from_options(options, 0.001)


def test_sophia_builds_a_threaded_simulated_driver(bazar):
    """The bundled world's ``simulated`` driver: threaded at 1 kHz for real-time runs."""
    driver = create_driver(bazar)
    assert isinstance(driver, ThreadedSimulatedDriver) and driver.realtime
    assert (driver.group.name, driver.period, driver.command_timeout) == (
        "bazar_upper_joints", 0.001, 0.05)


def test_faster_than_real_time_keeps_the_in_thread_driver(bazar):
    """Without real time, ``simulated`` is the in-thread driver stepping time_step."""
    driver = create_driver(bazar, realtime=False, time_step=0.005)
    assert isinstance(driver, SimulatedDriver) and driver.time_step == 0.005
    with pytest.raises(DriverConfigError, match="needs the control period"):
        create_driver(bazar, realtime=False)


def test_options_reach_the_drivers(tmp_path):
    """rate, command_timeout, state_timeout and port are read from the world file."""
    world = world_with(tmp_path, """
        arms: {type: simulated, options: {joint_group: bazar_arms, rate: 2kHz,
                                          command_timeout: 20ms, state_timeout: 1s}}
        head: {type: loopback, options: {joint_group: bazar_ptu, port: 50123}}
    """)
    arms = create_driver(world, "arms")
    head = create_driver(world, "head")
    assert (arms.period, arms.command_timeout, arms.state_timeout) == (0.0005, 0.02, 1.0)
    assert isinstance(head, LoopbackDriver) and (head.port, head.launch) == (50123, False)
    with pytest.raises(DriverConfigError, match="2 driver processors"):
        create_driver(world)
    with pytest.raises(DriverConfigError, match="no driver processor 'legs'"):
        create_driver(world, "legs")


@pytest.mark.parametrize("processors, message", [
    ("driver: {type: simulated, options: {}}", "needs option 'joint_group'"),
    ("driver: {type: simulated, options: {joint_group: bazar_tail}}",
     "unknown joint group or joint 'bazar_tail'"),
    ("driver: {type: simulated, options: {joint_group: bazar_arms, speed: 2}}",
     "unknown option 'speed' of a simulated processor"),
    ("driver: {type: loopback, options: {joint_group: bazar_arms}}", "needs option 'port'"),
    ("driver: {type: loopback, options: {joint_group: bazar_arms, port: 99999}}",
     "must be a TCP port"),
])
def test_bad_driver_processors(tmp_path, processors, message):
    """Each mistake in a driver processor is named when the world loads."""
    with pytest.raises(DiagnosticError, match=message):
        world_with(tmp_path, processors)


def test_ticker_skips_missed_ticks():
    """A late ticker counts the ticks it missed and does not burst to catch up."""
    now = [0.0]
    ticker = Ticker(0.01, clock=lambda: now[0])
    now[0] = 0.055
    assert ticker.wait() == 0.055
    assert ticker.missed == 4
    assert parse_rate("1.5kHz") == 1500.0
