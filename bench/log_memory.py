"""Memory and cost of the streamed run log over a long run.

One mission (two arms swinging between two postures, a body task enabled, so that the
log carries joint and task columns) runs headless for ``--duration`` seconds of mission
time (600 by default: 120 000 cycles at 5 ms), twice in this process: with the run log
(``RunLogger``, as ``run --log``) and without any observer. The table gives for each:

- RSS [MB] of this process (``/proc/self/status``) after the first tenth of the run, at
  its last cycle, and once the log is written (its row groups joined into one file);
  and the growth from the first tenth to the last cycle, per hour of mission time;
- mean and median cycle [us] (the whole cycle, observers included) and the wall time
  per cycle [us] (everything the process did, the writer thread's share and the final
  join included);
- the log's cost: each timing with the log over the same without.

The run without the log goes first, so that its memory figures are its own.

Usage: python bench/log_memory.py [--duration 600] [--mission FILE]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

from robocop_dsl.runtime import Observer, RunLogger, load_mission

SWING = """
mission swing
world "bazar/sophia.yaml"

event finish

constraint limits: joint_kinematic(bazar_upper_joints) {
    max_velocity     = 1 rad/s
    max_acceleration = 5 rad/s^2
}

task arms: joint_position(bazar_arms) {
    interpolator = otg(max_velocity = 0.5 rad/s, max_acceleration = 1 rad/s^2)
    priority     = 1
}
task left_tool: body_position(bazar_left_hankamp_tool_object_side) {
    reference = world
    priority  = 0
}

state out {
    enter { enable arms
            arms.target = [0.5, 0.5, 0, -1.5, 0, 0.7, 0, 0.5, 0.5, 0, -1.5, 0, 0.7, 0] rad }
    when elapsed > 5 s -> back
}
state back {
    enter { arms.target = [0, 0.25, 0, -2, 0, 0.7, 0, 0, 0.25, 0, -2, 0, 0.7, 0] rad }
    when elapsed > 5 s -> out
    when event finish -> done
}
final done
"""


def rss_mb() -> float:
    """This process's resident memory [MB]."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    raise RuntimeError("no VmRSS in /proc/self/status")


class Memory(Observer):
    """Samples the RSS after the first tenth of ``cycles``, at the last of them, and
    when the run stops (after the observers added before it)."""

    wants_tasks = False

    def __init__(self, cycles: int):
        self.marks = (cycles // 10, cycles - 1)
        self.early = self.late = self.stopped = 0.0

    def on_cycle(self, record) -> None:
        if record.cycle == self.marks[0]:
            self.early = rss_mb()
        elif record.cycle == self.marks[1]:
            self.late = rss_mb()

    def on_stop(self, result) -> None:
        self.stopped = rss_mb()


def run(mission, duration: float, with_log: bool) -> dict:
    runner = mission.runner()
    memory = Memory(round(duration / runner.time_step))
    if with_log:
        runner.add_observer(RunLogger(tempfile.mkdtemp(), runner.joint_names))
    runner.add_observer(memory)
    start = time.perf_counter()
    result = runner.run(duration=duration)
    wall = time.perf_counter() - start
    hours = 0.9 * duration / 3600
    return {"rss early": memory.early, "rss last cycle": memory.late,
            "rss log written": memory.stopped,
            "growth per hour": (memory.late - memory.early) / hours,
            "mean cycle": result.cycle_times.mean() * 1e6,
            "median cycle": np.median(result.cycle_times) * 1e6,
            "wall per cycle": wall / result.cycles * 1e6}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=600.0,
                        help="mission time of each run [s] (default 600)")
    parser.add_argument("--mission", help="a mission file instead of the built-in swing")
    args = parser.parse_args()
    if args.mission:
        mission = load_mission(args.mission)
    else:
        folder = Path(tempfile.mkdtemp())
        (folder / "swing.mission").write_text(SWING)
        mission = load_mission(folder / "swing.mission")
    bare = run(mission, args.duration, with_log=False)
    logged = run(mission, args.duration, with_log=True)
    table = Table(title=f"{args.duration:g} s of mission time, {mission.name}")
    units = {"rss early": "MB", "rss last cycle": "MB", "rss log written": "MB",
             "growth per hour": "MB/h",
             "mean cycle": "us", "median cycle": "us", "wall per cycle": "us"}
    for column in ("figure", "with --log", "without", "log / without"):
        table.add_column(column, justify="right")
    for name, unit in units.items():
        ratio = logged[name] / bare[name] if unit == "us" else float("nan")
        table.add_row(f"{name} ({unit})", f"{logged[name]:.1f}", f"{bare[name]:.1f}",
                      "" if np.isnan(ratio) else f"{ratio:.2f}")
    Console().print(table)


if __name__ == "__main__":
    main()
