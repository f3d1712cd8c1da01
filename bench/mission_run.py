"""How fast a mission runs headless, and what the runtime adds to the controller.

For each configuration, the same mission runs to its end in this process (best of
``--repeat`` runs) and the table gives:

- speed-up: mission time / the process's CPU time over the run (how much faster than
  real time the run would be with a core to itself; ``time.process_time``), and mission
  time / wall time;
- cycle and compute medians and p99 [us]: a whole cycle (driver, kinematics, state
  machine, QP, observers) and the controller's work alone (forward kinematics and
  ``compute()``);
- overhead: median cycle / median compute - 1, the runtime's share per cycle;
- log write [ms]: the run log's work after the last cycle (the task views it computes
  then, and the Parquet file).

Above the table: the mission's enabled ``collision_avoidance`` constraints (they run),
and the run's start-up: from a new interpreter's start to the end of its first cycle
(importing, loading the mission, building the runner), wall and CPU time, best of
``--repeat``.

Below the table: what the run log adds to the median cycle, against no observer, and
the memory it holds per cycle until it writes (one more run, under ``tracemalloc``).

With ``--viewer``, it then compares the cycle times of real-time runs headless, with
the live Meshcat viewer and with the replay recorder (``viewer_overhead.py``).

Usage: python bench/mission_run.py [--mission missions/pickup.mission] [--repeat 3]
       [--viewer]
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
import tracemalloc

import numpy as np
from rich.console import Console
from rich.table import Table

from robocop_dsl.runtime import RunLogger, load_mission


class TimedLogger(RunLogger):
    """The run log, timing its work when the run stops."""

    write_time = 0.0

    def on_stop(self, result) -> None:
        start = time.perf_counter()
        super().on_stop(result)
        self.write_time = time.perf_counter() - start


def run_once(mission, with_log: bool):
    runner = mission.runner()
    logger = None
    if with_log:
        logger = TimedLogger(tempfile.mkdtemp(), runner.joint_names)
        runner.add_observer(logger)
    start, cpu = time.perf_counter(), time.process_time()
    result = runner.run()
    cpu = time.process_time() - cpu
    wall = time.perf_counter() - start
    return result, wall, cpu, logger.write_time if logger else 0.0


FIRST_CYCLE = """
import sys, time
from robocop_dsl.runtime import load_mission
runner = load_mission(sys.argv[1]).runner()
runner.step()
print(time.process_time(), flush=True)
"""


def start_up(mission_path: str, repeat: int) -> tuple[float, float]:
    """Best wall and CPU times [s] from a new interpreter's start to the end of the
    mission's first cycle (the interpreter's own start-up included)."""
    walls, cpus = [], []
    for _ in range(repeat):
        start = time.perf_counter()
        child = subprocess.Popen([sys.executable, "-c", FIRST_CYCLE, mission_path],
                                 stdout=subprocess.PIPE, text=True)
        line = child.stdout.readline()
        walls.append(time.perf_counter() - start)
        child.wait()
        cpus.append(float(line))
    return min(walls), min(cpus)


def collision_constraints(mission) -> list[str]:
    """Names of the enabled ``collision_avoidance`` constraints once the mission starts."""
    runner = mission.runner()
    runner.step()
    return [c.name for c in runner.controller.constraints()
            if c.kind == "collision_avoidance" and c.enabled]


def log_memory(mission, cycles: int = 1000) -> float:
    """Bytes the run log holds per cycle, over ``cycles`` cycles after the first."""
    runner = mission.runner()
    runner.add_observer(RunLogger(tempfile.mkdtemp(), runner.joint_names))
    runner.step()
    tracemalloc.start()
    for _ in range(cycles):
        runner.step()
    held = tracemalloc.get_traced_memory()[0]
    tracemalloc.stop()
    return held / cycles


def measure(mission, with_log: bool, repeat: int) -> dict:
    best = None
    for _ in range(repeat):
        run = run_once(mission, with_log)
        if best is None or run[2] < best[2]:
            best = run
    result, wall, cpu, write = best
    cycles, compute = result.cycle_times * 1e6, result.compute_times * 1e6
    return {"outcome": result.outcome, "speed-up": result.mission_time / cpu,
            "wall speed-up": result.mission_time / wall,
            "cycle median": np.median(cycles), "cycle p99": np.percentile(cycles, 99),
            "compute median": np.median(compute), "compute p99": np.percentile(compute, 99),
            "overhead": np.median(cycles) / np.median(compute) - 1.0,
            "cycles": result.cycles, "write": write}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mission", default="missions/pickup.mission")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--viewer", action="store_true",
                        help="also compare real-time runs with the live viewer and recorder")
    args = parser.parse_args()
    mission = load_mission(args.mission)
    console = Console(width=170)
    avoiding = collision_constraints(mission)
    console.print(f"Collision constraints enabled: {', '.join(avoiding) or 'none'}")
    wall, cpu = start_up(args.mission, args.repeat)
    console.print(f"Start-up, new interpreter to the end of the first cycle: "
                  f"{wall * 1e3:.0f} ms wall, {cpu * 1e3:.0f} ms CPU")
    table = Table(title=f"{mission.name}: headless runs (best of {args.repeat})")
    columns = ("run", "outcome", "cycles", "speed-up (CPU)", "speed-up (wall)",
               "cycle median us", "cycle p99 us",
               "compute median us", "compute p99 us", "overhead", "log write ms")
    for column in columns:
        table.add_column(column, justify="right")
    rows = {}
    for label, with_log in (("no observer", False), ("with --log", True)):
        row = rows[label] = measure(mission, with_log, args.repeat)
        table.add_row(label, row["outcome"], str(row["cycles"]), f"{row['speed-up']:.1f}x",
                      f"{row['wall speed-up']:.1f}x",
                      f"{row['cycle median']:.1f}", f"{row['cycle p99']:.1f}",
                      f"{row['compute median']:.1f}", f"{row['compute p99']:.1f}",
                      f"{row['overhead'] * 100:.1f}%", f"{row['write'] * 1e3:.0f}")
    console.print(table)
    bare, logged = rows["no observer"]["cycle median"], rows["with --log"]["cycle median"]
    console.print(f"The run log adds {logged - bare:.1f} us to the median cycle "
                  f"({(logged / bare - 1) * 100:.1f}% of the cycle without observer).")
    console.print(f"It holds {log_memory(mission) / 1024:.1f} KiB per cycle until the run "
                  "stops and it writes.")
    if args.viewer:
        import viewer_overhead

        viewer_overhead.main(["--realtime", "--repeats", str(args.repeat),
                              "--mission", args.mission])


if __name__ == "__main__":
    main()
