"""The loopback robot simulator protects itself as a real robot would: a command with a
non-finite value is refused (the robot holds and says so), velocities are clamped to
the URDF's limits, and a client that stalls (idle, or in the middle of a frame) is
dropped so that the next driver is served. Each test talks to a real simulator process
over its TCP protocol and waits for frames, never for the clock."""

import re
import socket
import subprocess
import sys

import numpy as np
import pytest

from robocop_dsl.drivers import protocol
from robocop_dsl.drivers.loopback import LoopbackDriver

GROUP = "bazar_upper_joints"
FRAMES = 20000


@pytest.fixture
def simulator():
    """A simulator process for the BAZAR upper body that drops clients after 0.5 s of
    silence; yields its port."""
    process = subprocess.Popen(
        [sys.executable, "-m", "robocop_dsl.drivers.simulator", "--port", "0",
         "--world", "bazar/sophia.yaml", "--joint-group", GROUP, "--client-timeout", "0.5s"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = process.stdout.readline()
    match = re.search(r"listening on 127\.0\.0\.1:(\d+)", line)
    assert match, process.stderr.read()
    yield int(match.group(1)), process
    process.kill()
    process.wait()
    process.stdout.close()
    process.stderr.close()


class Client:
    """A driver speaking the protocol by hand."""

    def __init__(self, port: int):
        self.connection = protocol.Connection(socket.create_connection(
            (protocol.HOST, port), timeout=60))
        self.hello = protocol.decode_hello(self.connection.receive())
        self.sequence = 0

    def command(self, velocity) -> None:
        self.sequence += 1
        self.connection.send(protocol.COMMAND, self.sequence, 0.0,
                             protocol.command_payload(np.asarray(velocity, float)))

    def state(self) -> tuple:
        """The next STATE: position, velocity, holding."""
        while True:
            message = self.connection.receive()
            if message.kind == protocol.STATE:
                return protocol.decode_state(message, self.hello.nq, self.hello.nv)

    def state_where(self, condition, commanding=None) -> tuple:
        """The first STATE for which ``condition(position, velocity, holding)`` holds,
        re-sending ``commanding`` (a velocity) on each one meanwhile; fails after
        ``FRAMES`` states."""
        for _ in range(FRAMES):
            state = self.state()
            if condition(*state):
                return state
            if commanding is not None:
                self.command(commanding)
        pytest.fail(f"no such state in {FRAMES} frames")

    def close(self) -> None:
        self.connection.close()


def test_a_non_finite_command_is_refused_and_the_robot_holds(simulator):
    port, process = simulator
    client = Client(port)
    nv = client.hello.nv
    moving = np.full(nv, 0.1)
    client.state_where(lambda q, v, holding: not holding and v[0] == 0.1, moving)
    bad = moving.copy()
    bad[3] = np.nan
    position, velocity, holding = client.state_where(lambda q, v, h: h, bad)
    assert np.isfinite(position).all() and not velocity.any()
    client.close()
    again = Client(port)
    position, _, _ = again.state()
    assert np.isfinite(position).all()
    again.close()
    process.kill()
    assert "refused a command with a non-finite value" in process.stdout.read()


def test_velocities_are_clamped_to_the_urdf_limits(simulator, bazar):
    port, _ = simulator
    client = Client(port)
    limits = np.asarray(bazar.joint_group(GROUP).max_velocity)
    fast = np.full(client.hello.nv, 50.0)
    _, velocity, _ = client.state_where(lambda q, v, holding: not holding, fast)
    np.testing.assert_allclose(velocity, limits)
    assert np.all(velocity < 50.0)
    client.close()


def test_a_stalled_client_is_dropped_and_the_next_driver_served(simulator, bazar):
    """A client sends half a frame header and stops; a loopback driver connecting
    after it gets the robot once the stalled client is dropped."""
    port, process = simulator
    stalled = Client(port)
    stalled.connection.sock.sendall(protocol.HEADER.pack(
        protocol.MAGIC, protocol.VERSION, protocol.COMMAND, 8 * stalled.hello.nv, 1, 0.0)[:10])
    driver = LoopbackDriver(bazar, GROUP, port=port, connect_timeout=60)
    driver.connect()
    q, _ = driver.read()
    assert np.isfinite(q).all()
    driver.disconnect()
    stalled.close()
    process.kill()
    assert "client timeout" in process.stdout.read()
