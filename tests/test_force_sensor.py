"""Force sensors: their processor is checked when the world loads; the MuJoCo driver
reads what a body and what it carries exert on the environment (a resting cube weighs
on the table: negative z); the low-pass filter follows its first-order law; a loopback
robot's wrenches reach the runner; a reading that cannot be given says why."""

import math
import socket
import textwrap
import threading
import time

import numpy as np
import pytest

from robocop_dsl.diagnostics import DiagnosticError
from robocop_dsl.drivers import DriverFault, LoopbackDriver, RobotSimulator, protocol
from robocop_dsl.physics.driver import MujocoDriver
from robocop_dsl.runtime import Observer, load_mission
from robocop_dsl.runtime.driver import SimulatedDriver
from robocop_dsl.runtime.sensors import Sensors, SensorError
from robocop_dsl.world import load_world

PERIOD = 0.01
STEP = 0.001
G = 9.81
CUBE_MASS = 0.1
GROUP = "panda_all"
PATIENT = {"state_timeout": 5.0, "connect_timeout": 60.0}
"""Timeouts of the loopback driver long enough for a robot thread starved by a loaded
machine."""
POLLS = 10000


def world_file(folder, text: str):
    path = folder / "w.yaml"
    path.write_text(textwrap.dedent(text).lstrip("\n"))
    return path


def problems(folder, processors: str) -> list:
    """The diagnostics (code, line, message, hint) of the press world with more
    processors."""
    path = world_file(folder, "models:\n  - include: panda/panda_press.yaml\nprocessors:\n"
                      + textwrap.indent(textwrap.dedent(processors).strip("\n"), "  "))
    with pytest.raises(DiagnosticError) as caught:
        load_world(path)
    return [(d.code, d.span.line, d.message, d.hint) for d in caught.value.diagnostics]


@pytest.fixture(scope="module")
def press():
    return load_world("panda/panda_press.yaml")


@pytest.fixture(scope="module")
def resting(press):
    """The press world's physics after half a second: the cube rests on the table."""
    driver = MujocoDriver(press, GROUP, PERIOD, STEP)
    for _ in range(50):
        driver.read()
    return driver


# ---- the processor ------------------------------------------------------------------


def test_the_press_world_has_a_sensor_on_the_hand(press):
    sensor = press.processors["hand_sensor"]
    assert (sensor.type, sensor.options) == ("force_sensor", {"body": "panda_hand"})
    assert list(press.force_sensors()) == ["panda_hand"]
    assert Sensors(press).bodies == ("panda_hand",)


def test_an_unknown_body_is_located_with_a_guess(tmp_path):
    [(code, line, message, hint)] = problems(tmp_path, """
        wrist: {type: force_sensor, options: {body: panda_hnd}}""")
    assert (code, line) == ("unknown-body", 4)
    assert message == "'body' names unknown body 'panda_hnd'"
    assert hint == "did you mean 'panda_hand'?"


def test_the_body_is_required_and_the_filter_is_a_rate(tmp_path):
    found = problems(tmp_path, """
        a: {type: force_sensor, options: {filter: 20Hz}}
        b: {type: force_sensor, options: {body: cube_body, filter: -5Hz}}""")
    assert [(code, line) for code, line, _, _ in found] == [("missing-option", 4),
                                                            ("wrong-option", 5)]
    assert found[0][2] == "processor 'a' (force_sensor) needs option 'body'"
    assert found[1][2] == "'filter' must be a rate > 0, not -5Hz"


def test_two_sensors_on_one_body_are_an_error(tmp_path):
    [(code, line, message, hint)] = problems(tmp_path, """
        second: {type: force_sensor, options: {body: panda_hand, filter: 20Hz}}""")
    assert (code, line) == ("duplicate-sensor", 4)
    assert message == "body 'panda_hand' already has force sensor 'hand_sensor'"


def test_the_filter_is_read_in_hertz(tmp_path):
    world = load_world(world_file(tmp_path, """
        models:
          - include: panda/panda_press.yaml
        processors:
          hand_sensor: {type: force_sensor, options: {body: panda_hand, filter: 0.02kHz}}
    """))
    assert [s.cutoff for s in Sensors(world).sensors] == [20.0]


# ---- physics: the sign convention ----------------------------------------------------


def test_a_resting_cube_weighs_on_the_table(resting):
    """The cube exerts its weight on the table: force (0, 0, -m g), no torque about its
    centre; the table (and all it carries) pushes the cube up: +m g, with the moment of
    that force about the table's origin."""
    cube = resting.wrench("cube_body")
    np.testing.assert_allclose(cube, [0, 0, -CUBE_MASS * G, 0, 0, 0], atol=1e-4)
    table = resting.wrench("table")
    arm = resting.body_pose("cube_body").translation - resting.body_pose("table").translation
    np.testing.assert_allclose(table[:3], [0, 0, CUBE_MASS * G], atol=1e-4)
    np.testing.assert_allclose(table[3:], np.cross(arm, table[:3]), atol=1e-3)
    np.testing.assert_allclose(resting.wrench("panda_hand"), np.zeros(6))


def test_contacts_between_sets_of_bodies(resting):
    assert resting.contact(["cube_body"], ["table"])
    assert resting.contact(["table"], ["cube_body"])
    assert not resting.contact(["panda_hand", "panda_leftfinger"], ["table", "cube_body"])
    with pytest.raises(KeyError, match="no body 'cube' in the simulation"):
        resting.wrench("cube")
    assert resting.wrench("cube_body")[2] == pytest.approx(-CUBE_MASS * G, abs=1e-4)


def test_a_welded_part_is_carried_by_the_hand(press):
    """Attached, the cube's contacts count for the hand: the hand exerts the cube's
    force on the table; detached, the hand touches nothing again."""
    driver = MujocoDriver(press, GROUP, PERIOD, STEP)
    for _ in range(20):
        driver.read()
    driver.attach("cube_body", "panda_hand")
    for _ in range(5):
        driver.read()
    carried = driver.contacts.carried("panda_hand")
    assert carried[driver.contacts.body_id("cube_body")]
    assert carried[driver.contacts.body_id("panda_rightfinger")]
    assert not driver.contacts.carried("cube_body")[driver.contacts.body_id("panda_hand")]
    hand, cube = driver.wrench("panda_hand"), driver.wrench("cube_body")
    assert cube[2] < -0.1
    np.testing.assert_allclose(hand[:3], cube[:3], atol=1e-12)
    driver.detach("cube_body")
    driver.read()
    np.testing.assert_allclose(driver.wrench("panda_hand"), np.zeros(6))


# ---- the runtime's sensors -----------------------------------------------------------


def test_the_filter_is_first_order_and_smooths_an_impact(tmp_path, press):
    """A cube dropped 3 cm onto the table, read by two sensors from one physics: the
    filtered one (5 Hz) follows y += (1 - exp(-2 pi fc T)) (x - y) from the raw one's
    readings, peaks lower, and both settle at -m g."""
    world = load_world(world_file(tmp_path, """
        models:
          - include: panda/panda_pick.yaml
        processors:
          cube_sensor: {type: force_sensor, options: {body: cube_body, filter: 5Hz}}
    """))
    (tmp_path / "raw").mkdir()
    raw_world = load_world(world_file(tmp_path / "raw", """
        models:
          - include: panda/panda_pick.yaml
        processors:
          cube_sensor: {type: force_sensor, options: {body: cube_body}}
    """))
    q = world.initial_configuration()
    joint = world.model.frames[world.body_frame_id("cube_body")].parentJoint
    q[world.model.joints[joint].idx_q + 2] += 0.03
    driver = MujocoDriver(world, GROUP, PERIOD, STEP, initial=q)
    filtered, raw = Sensors(world), Sensors(raw_world)
    readings, smooth = [], []
    for _ in range(100):
        driver.read()
        filtered.update(driver, PERIOD)
        raw.update(driver, PERIOD)
        readings.append(raw.wrench("cube_body"))
        smooth.append(filtered.wrench("cube_body"))
    readings, smooth = np.array(readings), np.array(smooth)
    step = 1 - math.exp(-2 * math.pi * 5 * PERIOD)
    expected = [readings[0]]
    for reading in readings[1:]:
        expected.append(expected[-1] + step * (reading - expected[-1]))
    np.testing.assert_allclose(smooth, expected, atol=1e-12)
    assert readings[:, 2].min() < 3 * smooth[:, 2].min()       # the impact: 3 times lower
    assert np.abs(np.diff(smooth[:, 2])).sum() < np.abs(np.diff(readings[:, 2])).sum() / 2
    for final in (readings[-1], smooth[-1]):
        assert final[2] == pytest.approx(-CUBE_MASS * G, abs=0.01)


def test_a_reading_that_cannot_be_given_says_why(press):
    sensors = Sensors(press)
    driver = SimulatedDriver(press, GROUP, PERIOD)
    sensors.update(driver, PERIOD)
    with pytest.raises(SensorError, match="no force sensor on 'panda_hnd' "
                                          r"\(did you mean 'panda_hand'\?\); bodies with "
                                          r"one: 'panda_hand' \(hand_sensor\)"):
        sensors.wrench("panda_hnd")
    with pytest.raises(SensorError, match="force sensor 'hand_sensor' on 'panda_hand' has "
                                          "no reading: the driver .* measures no wrench"):
        sensors.wrench("panda_hand")
    with pytest.raises(SensorError, match=r"contact\(panda_hand, table\) needs a driver "
                                          "that simulates contacts"):
        sensors.contact("panda_hand", "table")
    assert sensors.readings() == {}


def test_contact_takes_bodies_and_joint_groups(press, resting):
    sensors = Sensors(press)
    sensors.update(resting, PERIOD)
    assert sensors.contact("cube_body", "table")
    assert not sensors.contact("panda_gripper", "table")
    assert not sensors.contact(GROUP, "cube_body")
    with pytest.raises(SensorError, match="'tabel' is neither a body, a joint group nor a "
                                          r"joint of the world \(did you mean 'table'\?\)"):
        sensors.contact("cube_body", "tabel")


# ---- the loopback protocol -----------------------------------------------------------


def test_hello_and_state_carry_the_sensors_and_old_frames_still_decode():
    hello = protocol.Hello(3, 2, 0.001, ("a", "b"), ("hand", "cube"))
    message = protocol.Message(protocol.HELLO, 0, 0.0, protocol.hello_payload(hello))
    assert protocol.decode_hello(message) == hello
    old = protocol.Hello(3, 2, 0.001, ("a", "b"))
    assert protocol.decode_hello(protocol.Message(
        protocol.HELLO, 0, 0.0, protocol.hello_payload(old))).sensors == ()
    wrenches = [[1, 2, 3, 4, 5, 6], [-1, -2, -3, -4, -5, -6]]
    payload = protocol.state_payload([1.0, 2.0, 3.0], [0.5, -0.5], True, wrenches)
    state = protocol.Message(protocol.STATE, 1, 0.0, payload)
    position, velocity, holding = protocol.decode_state(state, 3, 2, 2)
    assert position.tolist() == [1, 2, 3] and velocity.tolist() == [0.5, -0.5] and holding
    np.testing.assert_array_equal(protocol.decode_wrenches(state, 3, 2, 2), wrenches)
    with pytest.raises(protocol.ProtocolError, match="has 137 bytes, expected 41"):
        protocol.decode_state(state, 3, 2)


class Robot:
    """The robot simulator of the press world on a free port, in a thread."""

    def __init__(self, world):
        self.server = socket.create_server((protocol.HOST, 0))
        self.port = self.server.getsockname()[1]
        self.simulator = RobotSimulator(world, GROUP)
        self.thread = threading.Thread(target=self.simulator.serve, args=(self.server,),
                                       kwargs={"once": True, "log": lambda text: None},
                                       daemon=True)
        self.thread.start()

    def close(self):
        self.thread.join(timeout=60)
        self.server.close()


class Wrenches(Observer):
    wants_tasks = False

    def __init__(self):
        self.seen = []

    def on_cycle(self, record):
        self.seen.append(record.wrenches.get("panda_hand"))


def test_a_loopback_robots_wrench_reaches_the_runner(tmp_path, press):
    """Each wrench the robot reports is the runner's reading and its records' from the
    next cycle on."""
    path = tmp_path / "hold.mission"
    path.write_text('mission hold\nworld "panda/panda_press.yaml"\n'
                    "state wait { when elapsed > 10 s -> done }\nfinal done\n")
    mission = load_mission(path)
    robot = Robot(mission.world)
    reported = robot.simulator.wrenches["panda_hand"]
    reported[:] = [1.0, -2.0, -12.5, 0.1, 0.2, -0.3]
    runner = mission.runner(driver=LoopbackDriver(mission.world, GROUP, port=robot.port,
                                                  **PATIENT))
    watch = Wrenches()
    runner.add_observer(watch)
    for _ in range(5):
        runner.step()
        time.sleep(PERIOD)
    np.testing.assert_array_equal(runner.wrench("panda_hand"), reported)
    reported[:] = [0.0, 0.0, -3.0, 0.0, 0.0, 0.0]
    for _ in range(POLLS):
        if runner.wrench("panda_hand")[2] == -3.0:
            break
        runner.step()
        time.sleep(PERIOD)
    np.testing.assert_array_equal(runner.wrench("panda_hand"), reported)
    runner.finish()
    robot.close()
    assert watch.seen[0].tolist() == [1.0, -2.0, -12.5, 0.1, 0.2, -0.3]
    assert watch.seen[-1].tolist() == reported.tolist()


def test_a_robot_without_the_worlds_sensor_is_refused(press):
    robot = Robot(press)
    robot.simulator.wrenches.clear()
    driver = LoopbackDriver(press, GROUP, port=robot.port, **PATIENT)
    with pytest.raises(DriverFault, match="the robot reports no wrench of panda_hand "
                                          r"\(a force sensor of the world\); it reports: none"):
        driver.connect()
    robot.close()
