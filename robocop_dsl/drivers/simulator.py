"""A robot in a process of its own, for the loopback driver.

Run it with ``python -m robocop_dsl.drivers.simulator --port 50000`` (``--port 0``
picks a free port). It listens on 127.0.0.1 only, prints one line
``robot simulator: ... listening on 127.0.0.1:PORT`` once ready, then serves one driver
at a time with the frames of :mod:`robocop_dsl.drivers.protocol`: a ``HELLO`` on
connection, then a ``STATE`` every cycle. It integrates the latest ``COMMAND`` like a
perfect velocity-controlled robot and holds (zero velocity) when the command is older
than the command timeout or the driver is gone. Its state outlives connections. It
reports a wrench for each force sensor of its world: zero (it touches nothing) unless
set in :attr:`RobotSimulator.wrenches`.

Like a real robot it protects itself: a command with a non-finite value is refused
(the robot holds and says so), velocities are clamped to the URDF's limits, and a
driver that sends no complete frame for the client timeout (idle, or stalled in the
middle of a frame) is dropped, so that the next driver can connect.
"""

from __future__ import annotations

import argparse
import socket
import sys
import time

import numpy as np
import pinocchio as pin

from . import protocol
from .base import DEFAULT_COMMAND_TIMEOUT
from .simulated import DEFAULT_PERIOD
from .timing import Ticker, parse_duration, parse_rate

DEFAULT_WORLD = "bazar/sophia.yaml"
DEFAULT_CLIENT_TIMEOUT = 5.0
"""[s] without a complete frame from the driver before it is dropped."""


class RobotSimulator:
    """A velocity-controlled robot serving drivers over TCP.

    Args:
        world: The world (its model gives the configuration space).
        joint_group: The robot's joints, as a group of the world.
        period: The robot's cycle [s].
        command_timeout: Age [s], counted from reception, beyond which a command is
            ignored.
        client_timeout: Time [s] without a complete frame from the driver after which
            it is dropped.

    Attributes:
        refused: How many commands were refused for a non-finite value.
        clamped: How many commands had a velocity above the URDF's limit.
        wrenches: The wrench each force sensor of the world reports, by body:
            ``[fx, fy, fz, tx, ty, tz]`` [N, N m] (zero; change it in place).
    """

    def __init__(self, world, joint_group: str, period: float = DEFAULT_PERIOD,
                 command_timeout: float = DEFAULT_COMMAND_TIMEOUT,
                 client_timeout: float = DEFAULT_CLIENT_TIMEOUT):
        self.model = pin.Model(world.model)
        self.group = world.joint_group(joint_group)
        self.period = float(period)
        self.command_timeout = float(command_timeout)
        self.client_timeout = float(client_timeout)
        self.max_velocity = np.asarray(self.group.max_velocity, dtype=float)
        self.q = world.initial_configuration()
        self.sequence = 0
        self.refused = 0
        self.clamped = 0
        self.wrenches = {body: np.zeros(protocol.WRENCH) for body in world.force_sensors()}

    def hello(self) -> protocol.Hello:
        """What the robot tells a driver on connection."""
        return protocol.Hello(len(self.group.q_indices), self.group.dofs, self.period,
                              self.group.joints, tuple(self.wrenches))

    def serve(self, server: socket.socket, once: bool = False, log=print) -> None:
        """Accept drivers one after the other; stop after the first if ``once``."""
        while True:
            client, address = server.accept()
            log(f"driver connected from {address[0]}:{address[1]}")
            reason = self.serve_driver(protocol.Connection(client), log)
            client.close()
            log(f"driver gone ({reason}): holding")
            if once:
                return

    def serve_driver(self, connection: protocol.Connection, log=print) -> str:
        """Run the robot for one driver until it leaves or is dropped; return why."""
        connection.sock.settimeout(1.0)
        velocity = np.zeros(self.model.nv)
        ticker = Ticker(self.period)
        last = heard = time.monotonic()
        command, received = None, -np.inf
        try:
            connection.send(protocol.HELLO, 0, last, protocol.hello_payload(self.hello()))
            while True:
                now = ticker.wait()
                self.q = pin.integrate(self.model, self.q, velocity * (now - last))
                last = now
                messages = connection.poll()
                if messages:
                    heard = now
                elif now - heard > self.client_timeout:
                    return (f"no complete frame for {self.client_timeout:g} s "
                            f"(client timeout)")
                for message in messages:
                    if message.kind == protocol.COMMAND:
                        command = self.accept(protocol.decode_command(message,
                                                                      self.group.dofs), log)
                        received = now
                holding = command is None or now - received > self.command_timeout
                velocity[self.group.v_indices] = 0.0 if holding else command
                self.sequence += 1
                connection.send(protocol.STATE, self.sequence, now, protocol.state_payload(
                    self.q[self.group.q_indices], velocity[self.group.v_indices], holding,
                    list(self.wrenches.values())))
        except (OSError, protocol.ProtocolError) as error:
            return str(error) or type(error).__name__

    def accept(self, command: np.ndarray, log=print) -> np.ndarray | None:
        """The velocity [rad/s or m/s] to follow for a received ``command``: ``None``
        (hold) for a non-finite one, else clamped to the URDF's velocity limits."""
        if not np.isfinite(command).all():
            self.refused += 1
            log(f"refused a command with a non-finite value ({self.refused} so far): "
                "holding")
            return None
        clamped = np.clip(command, -self.max_velocity, self.max_velocity)
        if not np.array_equal(clamped, command):
            self.clamped += 1
            if self.clamped == 1:
                log("clamped a command to the URDF's velocity limits")
        return clamped


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python -m robocop_dsl.drivers.simulator",
        description="A simulated velocity-controlled robot for the loopback driver.")
    parser.add_argument("--port", type=int, required=True,
                        help="TCP port on 127.0.0.1 (0: any free port)")
    parser.add_argument("--world", default=DEFAULT_WORLD,
                        help=f"world file (default {DEFAULT_WORLD})")
    parser.add_argument("--joint-group", help="the robot's joints (default: the group of "
                                              "the world's driver processor)")
    parser.add_argument("--rate", default="1kHz", help="robot cycle rate (default 1kHz)")
    parser.add_argument("--command-timeout", default="50ms",
                        help="hold when the last command is older (default 50ms)")
    parser.add_argument("--client-timeout", default=f"{DEFAULT_CLIENT_TIMEOUT:g}s",
                        help="drop a driver that sends no complete frame for this long "
                             f"(default {DEFAULT_CLIENT_TIMEOUT:g}s)")
    parser.add_argument("--once", action="store_true", help="exit when the driver leaves")
    parser.add_argument("--quiet", action="store_true",
                        help="print only the line announcing the port")
    return parser


def default_joint_group(world) -> str | None:
    """The joint group of the world's first processor that has one and is a driver."""
    for processor in world.processors.values():
        if processor.type in ("simulated", "loopback") and "joint_group" in processor.options:
            return processor.options["joint_group"]
    return None


def main(argv: list | None = None) -> int:
    """Run the simulator; exit code 0 when stopped, 2 on bad arguments."""
    from ..diagnostics import RobocopError
    from ..world import load_world

    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        world = load_world(args.world)
        group = args.joint_group or default_joint_group(world)
        if group is None:
            parser.error(f"{args.world} has no driver processor: give --joint-group")
        simulator = RobotSimulator(world, group, 1.0 / parse_rate(args.rate),
                                   parse_duration(args.command_timeout, "command timeout"),
                                   parse_duration(args.client_timeout, "client timeout"))
    except RobocopError as error:
        print(f"robot simulator: {error}", file=sys.stderr)
        return 2
    except KeyError as error:
        print(f"robot simulator: {args.world} has no joint group or joint {error}",
              file=sys.stderr)
        return 2
    server = socket.create_server((protocol.HOST, args.port))
    port = server.getsockname()[1]
    print(f"robot simulator: {group} ({simulator.group.dofs} dofs) at "
          f"{1 / simulator.period:g} Hz, listening on {protocol.HOST}:{port}", flush=True)
    log = (lambda text: None) if args.quiet else (lambda text: print(text, flush=True))
    try:
        simulator.serve(server, once=args.once, log=log)
    except KeyboardInterrupt:
        pass
    finally:
        server.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
