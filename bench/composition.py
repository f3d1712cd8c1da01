"""What composition costs per cycle: a composed mission against the flat pickup.

Both missions run headless to their end in this process, alternately, ``--repeat``
times each; the table gives, for the fastest run of each, the cycle count, the median
and p99 of the whole cycle [us], the median of the controller's work (kinematics and
QP) and the median of the rest (driver, state machine, actions) [us], then the ratio of
the composed mission's figures to the flat one's. The two missions solve different QPs
(two_parts enables a gaze task too), so the state machine's share, the rest, is the
figure that says what nested machines cost.

Usage: python bench/composition.py [--composed missions/two_parts.mission]
       [--flat missions/pickup.mission] [--repeat 5]
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


def figures(result) -> dict:
    cycles, compute = result.cycle_times * 1e6, result.compute_times * 1e6
    return {"outcome": result.outcome, "cycles": result.cycles,
            "cycle median": float(np.median(cycles)),
            "cycle p99": float(np.percentile(cycles, 99)),
            "compute median": float(np.median(compute)),
            "rest median": float(np.median(cycles - compute))}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--composed", default="missions/two_parts.mission")
    parser.add_argument("--flat", default="missions/pickup.mission")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    missions = {"flat": load_mission(args.flat), "composed": load_mission(args.composed)}
    best: dict = {}
    for _ in range(args.repeat):
        for label, mission in missions.items():
            result, wall = run_once(mission)
            if label not in best or wall < best[label][1]:
                best[label] = (result, wall)
    rows = {label: figures(result) for label, (result, _) in best.items()}
    table = Table(title=f"composition per cycle (best of {args.repeat})")
    keys = ("cycle median", "cycle p99", "compute median", "rest median")
    for column in ("mission", "outcome", "cycles", *(f"{k} us" for k in keys)):
        table.add_column(column, justify="right")
    for label, mission in missions.items():
        row = rows[label]
        table.add_row(f"{label}: {mission.name}", row["outcome"], str(row["cycles"]),
                      *(f"{row[k]:.1f}" for k in keys))
    table.add_row("composed / flat", "", "",
                  *(f"{rows['composed'][k] / rows['flat'][k]:.2f}x" for k in keys))
    Console(width=160).print(table)


if __name__ == "__main__":
    main()
