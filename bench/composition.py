"""What composition costs per cycle: composed missions against the flat pickup.

``bench/pickup_flat.mission`` is the pickup written as one flat machine;
``missions/pickup.mission`` makes the same motions through a behaviour (a nested machine
per step), and ``missions/two_parts.mission`` moves two parts through two levels of
behaviours. All run headless to their end in this process, in turn, ``--repeat`` times
each; the table gives, for the fastest run of each, the cycle count, the median and p99
of the whole cycle and of the controller's work (kinematics and QP) and the median of
the rest (driver, state machine, actions) [us], and each figure's ratio to the flat
pickup's. The flat and composed pickups solve the same QPs, so their ratio is what the
nesting costs; two_parts solves other QPs (a gaze task too), so its rest is the figure
to compare.

Usage: python bench/composition.py [--repeat 5] [MISSION...]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from rich.console import Console
from rich.table import Table

from robocop_dsl.runtime import load_mission


def run_once(mission) -> tuple:
    runner = mission.runner()
    start = time.perf_counter()
    result = runner.run()
    return result, time.perf_counter() - start


KEYS = ("cycle median", "cycle p99", "compute median", "compute p99", "rest median")
FLAT = "bench/pickup_flat.mission"
COMPOSED = ("missions/pickup.mission", "missions/two_parts.mission")


def figures(result) -> dict:
    cycles, compute = result.cycle_times * 1e6, result.compute_times * 1e6
    return {"outcome": result.outcome, "cycles": result.cycles,
            "cycle median": float(np.median(cycles)),
            "cycle p99": float(np.percentile(cycles, 99)),
            "compute median": float(np.median(compute)),
            "compute p99": float(np.percentile(compute, 99)),
            "rest median": float(np.median(cycles - compute))}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("missions", nargs="*", default=list(COMPOSED))
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    missions = [load_mission(path) for path in (FLAT, *args.missions)]
    best: dict = {}
    for _ in range(args.repeat):
        for mission in missions:
            result, wall = run_once(mission)
            if mission.name not in best or wall < best[mission.name][1]:
                best[mission.name] = (result, wall)
    rows = {name: figures(result) for name, (result, _) in best.items()}
    flat = rows[missions[0].name]
    table = Table(title=f"composition per cycle (best of {args.repeat}; ratio to the "
                  "flat pickup)")
    for column in ("mission", "outcome", "cycles", *(f"{k} us" for k in KEYS)):
        table.add_column(column, justify="right")
    for mission in missions:
        row = rows[mission.name]
        table.add_row(mission.name, row["outcome"], str(row["cycles"]),
                      *(f"{row[k]:.1f} ({row[k] / flat[k]:.2f}x)" for k in KEYS))
    Console(width=180).print(table)


if __name__ == "__main__":
    main()
