"""Starting the robot simulator as a child process."""

from __future__ import annotations

import re
import subprocess
import sys

from .errors import DriverFault

_READY = re.compile(r"listening on 127\.0\.0\.1:(\d+)")
CAUSE_LINES = 5   # lines of the simulator's output quoted when it does not start


def last_lines(text: str, count: int = CAUSE_LINES) -> str:
    """The last ``count`` non-blank lines of ``text``, joined by newlines."""
    lines = [line.rstrip() for line in text.splitlines() if line.strip()]
    return "\n".join(lines[-count:])


class SimulatorProcess:
    """``python -m robocop_dsl.drivers.simulator`` run as a child of this process.

    Args:
        world: Path of the world file.
        joint_group: The robot's joints.
        rate: The robot's cycle rate [Hz].
        command_timeout: The robot's command timeout [s].
        port: TCP port on 127.0.0.1; 0 lets the simulator pick a free one.
    """

    def __init__(self, world, joint_group: str, rate: float = 1000.0,
                 command_timeout: float = 0.05, port: int = 0):
        self.args = [sys.executable, "-m", "robocop_dsl.drivers.simulator",
                     "--port", str(port), "--world", str(world), "--joint-group", joint_group,
                     "--rate", f"{rate:g}Hz", "--command-timeout", f"{command_timeout:g}s",
                     "--quiet"]
        self.process: subprocess.Popen | None = None
        self.port: int | None = None

    def __repr__(self) -> str:
        return f"SimulatorProcess(port={self.port}, running={self.running})"

    def __enter__(self):
        self.start()
        return self

    def __exit__(self, *exc) -> None:
        self.stop()

    @property
    def running(self) -> bool:
        return self.process is not None and self.process.poll() is None

    def start(self) -> int:
        """Start the simulator and wait for the line announcing its port.

        Returns:
            The port it listens on.

        Raises:
            DriverFault: The simulator exited before listening; the message quotes the
                last lines of its stderr (else of its stdout).
        """
        self.process = subprocess.Popen(self.args, stdout=subprocess.PIPE,
                                        stderr=subprocess.PIPE, text=True)
        printed = []
        for line in self.process.stdout:
            match = _READY.search(line)
            if match is not None:
                self.port = int(match.group(1))
                return self.port
            printed.append(line)
        status = self.process.wait()
        cause = last_lines(self.process.stderr.read()) or last_lines("".join(printed))
        raise DriverFault("robot simulator",
                          f"did not start (exit code {status}): {cause or 'no output'}")

    def stop(self) -> None:
        """Terminate the simulator (SIGTERM, then SIGKILL after 5 s) and reap it."""
        if self.process is None:
            return
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(5.0)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self.process.stdout.close()
        self.process.stderr.close()
        self.process = None

    def kill(self) -> None:
        """Kill the simulator at once, as a robot losing power would vanish."""
        if self.process is not None and self.process.poll() is None:
            self.process.kill()
            self.process.wait()
