"""The loopback driver: a robot in another process, reached over TCP on 127.0.0.1.

It is how a real robot driver plugs in: a driver thread keeps the connection, turns
the robot's ``STATE`` frames into states for the world and the controller's commands
into ``COMMAND`` frames; the controller thread only copies. The world's force sensors
are read from the robot: it must report each of them.
"""

from __future__ import annotations

import socket
import time

import numpy as np

from . import protocol
from .base import DEFAULT_COMMAND_TIMEOUT, ThreadedDriver
from .errors import DriverFault
from .process import SimulatorProcess


class LoopbackDriver(ThreadedDriver):
    """Drives the robot simulator (or any robot speaking the protocol) over loopback.

    Losing the connection, no ``STATE`` for ``state_timeout``, or a ``STATE`` whose
    sequence number does not advance past the previous one's (a frozen robot) is a
    fault: the next ``read()``/``write()`` raises :class:`DriverFault`, and the robot
    holds on its own once its command times out.

    Args:
        world: The world (its model gives the configuration space).
        joint_group: The driven group's name; the robot must announce the same joints.
        port: TCP port of the robot on 127.0.0.1; with ``launch``, 0 or ``None`` picks
            a free one.
        launch: Start the simulator as a child process on ``connect()`` and stop it on
            ``disconnect()``.
        rate: Cycle rate of a launched simulator [Hz].
        command_timeout: Command timeout of a launched simulator [s].
        sensors: The bodies whose wrenches the robot must report; default those of the
            world's force sensors.
        **kwargs: ``state_timeout``, ``connect_timeout``, ``initial`` of
            :class:`~robocop_dsl.drivers.base.ThreadedDriver`.
    """

    def __init__(self, world, joint_group: str, port: int | None = None,
                 launch: bool = False, rate: float = 1000.0,
                 command_timeout: float = DEFAULT_COMMAND_TIMEOUT,
                 sensors: tuple | None = None, **kwargs):
        super().__init__(world, joint_group, sensors=tuple(
            world.force_sensors() if sensors is None else sensors), **kwargs)
        self.port = port
        self.launch = launch
        self.rate = float(rate)
        self.command_timeout = float(command_timeout)
        self.simulator: SimulatorProcess | None = None
        self.hello: protocol.Hello | None = None
        self._connection: protocol.Connection | None = None

    def __repr__(self) -> str:
        return (f"LoopbackDriver({self.group.name}, {self.group.dofs} dofs, "
                f"{protocol.HOST}:{self.port})")

    def _open(self) -> None:
        if self.launch:
            self.simulator = SimulatorProcess(self.world.path, self.group.name, self.rate,
                                              self.command_timeout, self.port or 0)
            self.port = self.simulator.start()
        try:
            self._connection = self._handshake()
        except (OSError, protocol.ProtocolError, DriverFault) as error:
            self._close()
            if isinstance(error, DriverFault):
                raise
            raise DriverFault(repr(self), f"cannot reach the robot: {error}") from error

    def _handshake(self) -> protocol.Connection:
        sock = socket.create_connection((protocol.HOST, self.port), self.connect_timeout)
        connection = protocol.Connection(sock)
        message = connection.receive()
        if message.kind != protocol.HELLO:
            raise protocol.ProtocolError(f"expected HELLO, got frame kind {message.kind}")
        self.hello = protocol.decode_hello(message)
        if (self.hello.joints != self.group.joints or self.hello.nv != self.group.dofs
                or self.hello.nq != len(self.group.q_indices)):
            connection.close()
            raise DriverFault(repr(self), f"the robot drives {list(self.hello.joints)}, "
                                          f"not the group's {list(self.group.joints)}")
        missing = [body for body in self.sensors if body not in self.hello.sensors]
        if missing:
            connection.close()
            raise DriverFault(repr(self), f"the robot reports no wrench of "
                                          f"{', '.join(missing)} (a force sensor of the "
                                          f"world); it reports: "
                                          f"{', '.join(self.hello.sensors) or 'none'}")
        sock.settimeout(self.state_timeout)
        return connection

    def wrench(self, body: str) -> np.ndarray:
        """The wrench the robot reported in its latest state for the force sensor on
        ``body``: ``[fx, fy, fz, tx, ty, tz]`` [N, N m], what the body exerts on the
        environment, world frame.

        Raises:
            DriverFault: ``body`` is not one of :attr:`sensors`, or no state was read.
        """
        if body not in self.sensors or self.last_state is None:
            raise DriverFault(repr(self), f"no wrench of '{body}' read from the robot "
                                          f"(its force sensors: "
                                          f"{', '.join(self.sensors) or 'none'})")
        return self.last_state.wrenches[self.sensors.index(body)].copy()

    def _serve(self) -> None:
        connection = self._connection
        nq, nv, reported = self.hello.nq, self.hello.nv, len(self.hello.sensors)
        mine = [self.hello.sensors.index(body) for body in self.sensors]
        sent, sequence = 0, -1
        while not self._stop.is_set():
            message = connection.receive()
            if message.kind == protocol.STATE:
                if message.sequence <= sequence:
                    raise protocol.ProtocolError(
                        f"STATE sequence number {message.sequence} does not advance past "
                        f"the previous one ({sequence}): the robot's state is stale")
                sequence = message.sequence
                position, velocity, holding = protocol.decode_state(message, nq, nv,
                                                                    reported)
                wrenches = protocol.decode_wrenches(message, nq, nv, reported)[mine]
                self._publish(position, velocity, holding, time.monotonic(), wrenches)
            command = self.reader.sync()
            if command is not None and command.sequence != sent:
                connection.send(protocol.COMMAND, command.sequence, command.time,
                                protocol.command_payload(command.velocity))
                sent = command.sequence
        connection.send(protocol.COMMAND, sent + 1, time.monotonic(),
                        protocol.command_payload(np.zeros(nv)))

    def _describe(self, error: Exception) -> str:
        where = f"{protocol.HOST}:{self.port}"
        if isinstance(error, TimeoutError):
            return f"no state from the robot at {where} for {self.state_timeout:g} s"
        if isinstance(error, ConnectionError):
            return f"connection to the robot at {where} lost ({error})"
        if isinstance(error, protocol.ProtocolError):
            return f"the robot at {where} broke the protocol: {error}"
        return super()._describe(error)

    def _close(self) -> None:
        if self._connection is not None:
            self._connection.close()
            self._connection = None
        if self.simulator is not None:
            self.simulator.stop()
            self.simulator = None
