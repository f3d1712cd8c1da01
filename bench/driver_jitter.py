"""Control-loop jitter with each driver: the in-thread simulated driver, the threaded
simulated driver (1 kHz thread) and the loopback driver (simulator process).

The loop is the runner's: wake at ``start + k * period``, read the driver, compute a
kinematic command for the left tool (forward kinematics, Jacobian, damped least
squares towards a moving target), write the driver. Reported per driver [ms]: the
period between cycle starts (median, p99, jitter = p99 - median, max), the time the
controller thread spends in ``read()`` + ``write()`` (median, p99) and late cycles.

Run: ``python bench/driver_jitter.py [--cycles 2000] [--period 5ms]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import pinocchio as pin

from robocop_dsl.drivers import LoopbackDriver, ThreadedSimulatedDriver
from robocop_dsl.drivers.timing import parse_duration
from robocop_dsl.runtime.driver import SimulatedDriver
from robocop_dsl.world import load_world

WORLD = "bazar/sophia.yaml"
GROUP = "bazar_upper_joints"
TOOL = "bazar_left_hankamp_tool_object_side"


class ToolTracking:
    """The controller's work in one cycle: move the left tool along a 5 cm circle.

    Args:
        world: The world.
        period: Control period [s].
    """

    def __init__(self, world, period: float):
        self.model = world.model
        self.data = self.model.createData()
        self.frame = world.body_frame_id(TOOL)
        self.columns = world.joint_group(GROUP).v_indices
        self.period = period
        self.centre = None

    def command(self, q: np.ndarray, cycle: int) -> np.ndarray:
        """Joint velocities [rad/s] of the group moving the tool towards its target."""
        pin.forwardKinematics(self.model, self.data, q)
        pose = pin.updateFramePlacement(self.model, self.data, self.frame)
        if self.centre is None:
            self.centre = pose.translation.copy()
        angle = 2 * np.pi * 0.2 * cycle * self.period
        target = self.centre + 0.05 * np.array([np.cos(angle) - 1, np.sin(angle), 0])
        jacobian = pin.computeFrameJacobian(self.model, self.data, q, self.frame,
                                            pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        jacobian = jacobian[:3, self.columns]
        error = 2.0 * (target - pose.translation)
        damped = jacobian @ jacobian.T + 1e-4 * np.eye(3)
        return jacobian.T @ np.linalg.solve(damped, error)


def run_loop(driver, world, period: float, cycles: int) -> dict:
    """Run the paced loop against ``driver``; return its timings [s]."""
    work = ToolTracking(world, period)
    starts, io_times = np.zeros(cycles), np.zeros(cycles)
    late = 0
    begin = time.perf_counter()
    for cycle in range(cycles):
        starts[cycle] = time.perf_counter()
        q, _ = driver.read()
        io = time.perf_counter() - starts[cycle]
        velocity = work.command(q, cycle)
        before_write = time.perf_counter()
        driver.write(velocity)
        io_times[cycle] = io + time.perf_counter() - before_write
        remaining = begin + (cycle + 1) * period - time.perf_counter()
        if remaining > 0:
            time.sleep(remaining)
        else:
            late += 1
    return {"periods": np.diff(starts), "io": io_times, "late": late}


def measure(name: str, world, period: float, cycles: int) -> dict:
    """Build driver ``name``, run the loop and summarise the timings [ms]."""
    if name == "in-thread":
        driver = SimulatedDriver(world, GROUP, period)
        timings = run_loop(driver, world, period, cycles)
    else:
        driver = (ThreadedSimulatedDriver(world, GROUP) if name == "threaded"
                  else LoopbackDriver(world, GROUP, launch=True))
        with driver:
            timings = run_loop(driver, world, period, cycles)
    ms = {key: value * 1e3 for key, value in timings.items() if key != "late"}
    median, p99 = np.percentile(ms["periods"], [50, 99])
    return {"driver": name, "median": median, "p99": p99, "jitter": p99 - median,
            "max": ms["periods"].max(), "io_median": np.median(ms["io"]),
            "io_p99": np.percentile(ms["io"], 99), "late": timings["late"]}


def table(rows: list, period: float, cycles: int) -> str:
    """The results as a Markdown table."""
    lines = [f"control period {period * 1e3:g} ms, {cycles} cycles per driver; times in ms",
             "",
             "| driver | period median | period p99 | jitter (p99 - median) | period max "
             "| read+write median | read+write p99 | late cycles |",
             "|---|---|---|---|---|---|---|---|"]
    for row in rows:
        lines.append(f"| {row['driver']} | {row['median']:.3f} | {row['p99']:.3f} | "
                     f"{row['jitter']:.3f} | {row['max']:.3f} | {row['io_median']:.4f} | "
                     f"{row['io_p99']:.4f} | {row['late']} |")
    return "\n".join(lines)


def main(argv: list | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cycles", type=int, default=2000, help="cycles per driver")
    parser.add_argument("--period", default="5ms", help="control period (default 5ms)")
    parser.add_argument("--drivers", nargs="+", default=["in-thread", "threaded", "loopback"],
                        choices=["in-thread", "threaded", "loopback"])
    args = parser.parse_args(argv)
    period = parse_duration(args.period, "period")
    world = load_world(WORLD)
    rows = [measure(name, world, period, args.cycles) for name in args.drivers]
    print(table(rows, period, args.cycles))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
