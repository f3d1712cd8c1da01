"""How much the physics costs a headless run: the Panda pick with the MuJoCo driver and
the same mission with the kinematic ``simulated`` driver, in turns, in one process
pinned to one core.

Each run is ``runner.run()`` headless (no log, no viewer), timed on the wall clock
from its first cycle to its end; its speed-up is mission time over wall time. For
the physics runs, the share of the wall time spent in MuJoCo's steps
(``driver.step_time``) and in the whole driver (``read()``: servo targets, steps,
reading the state back) is printed too. The kinematic run fails its mission (the
cube does not move: nothing lifts it), so it runs longer; speed-ups are ratios, not
totals. Medians over ``--rounds`` turns.

Usage: ``python bench/physics_speed.py [--rounds N] [--cpu K]``
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

from rich.console import Console
from rich.table import Table

from robocop_dsl.runtime import load_mission
from robocop_dsl.world import load_world

REPO = Path(__file__).resolve().parent.parent
MISSION = REPO / "missions" / "panda_pick.mission"
KINEMATIC = """\
models:
  - include: panda/panda_pick.yaml
processors:
  driver:
    type: simulated
    options: {joint_group: panda_all}
"""


def timed_run(mission) -> dict:
    """One headless run: wall time [s], mission time [s], MuJoCo's and the driver's
    time [s] (zero without physics)."""
    runner = mission.runner()
    driver = runner.driver
    spent = [0.0]
    read = driver.read

    def timed_read():
        started = time.perf_counter()
        try:
            return read()
        finally:
            spent[0] += time.perf_counter() - started

    driver.read = timed_read
    started = time.perf_counter()
    result = runner.run()
    wall = time.perf_counter() - started
    return {"wall": wall, "mission": result.mission_time, "outcome": result.outcome,
            "mujoco": getattr(driver, "step_time", 0.0), "driver": spent[0]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--cpu", type=int, default=0, help="the core to run on")
    args = parser.parse_args()
    os.sched_setaffinity(0, {args.cpu})
    with tempfile.TemporaryDirectory() as folder:
        variant = Path(folder) / "kinematic.yaml"
        variant.write_text(KINEMATIC)
        missions = {"physics (mujoco)": load_mission(MISSION),
                    "kinematic (simulated)": load_mission(MISSION, world=load_world(variant))}
        runs: dict = {name: [] for name in missions}
        for mission in missions.values():
            timed_run(mission)                     # warm-up: imports, first allocations
        for _ in range(args.rounds):
            for name, mission in missions.items():
                runs[name].append(timed_run(mission))
    table = Table(title=f"Panda pick, headless, one core (cpu {args.cpu}), median of "
                        f"{args.rounds}")
    for column in ("driver", "outcome", "mission time", "wall time", "speed-up",
                   "MuJoCo share", "driver share"):
        table.add_column(column, justify="left" if column in ("driver", "outcome")
                         else "right")
    for name, results in runs.items():
        median = {key: statistics.median(r[key] for r in results)
                  for key in ("wall", "mission", "mujoco", "driver")}
        speed = statistics.median(r["mission"] / r["wall"] for r in results)
        mujoco = statistics.median(r["mujoco"] / r["wall"] for r in results)
        driver = statistics.median(r["driver"] / r["wall"] for r in results)
        table.add_row(name, results[0]["outcome"], f"{median['mission']:.2f} s",
                      f"{median['wall']:.3f} s", f"{speed:.1f}x",
                      f"{mujoco:.0%}" if mujoco else "-", f"{driver:.0%}")
    Console().print(table)


if __name__ == "__main__":
    main()
