"""Reaching success of this controller and of Pink on the fixed-base arms of
example-robot-data, on the same seeded targets (see ``tests/arm_reaching.py``).

For each arm: ``--targets`` problems (a start in the joint ranges, a target pose of the
tool given by forward kinematics of a configuration nearby), each run for a fixed
number of cycles by both controllers in this process. Columns: targets reached,
joint-limit violations (samples past a limit by more than 1e-6), whether every
command was finite, the median time per problem, and the ratio of Pink's reached
count to ours.

Usage: ``python bench/arm_sweep.py [--targets N] [--seed S]``
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

from arm_reaching import ARMS, arm, problems, run_ours, run_pink  # noqa: E402


def timed(run, world, group, tool, cases) -> tuple[list, float]:
    outcomes, times = [], []
    for case in cases:
        start = time.perf_counter()
        outcomes.append(run(world, group, tool, case))
        times.append(time.perf_counter() - start)
    return outcomes, sorted(times)[len(times) // 2]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--targets", type=int, default=20)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    print(f"{'arm':<18}{'dofs':>5}{'ours':>7}{'Pink':>7}{'viol ours':>11}{'viol Pink':>11}"
          f"{'finite':>8}{'ms ours':>9}{'ms Pink':>9}{'Pink/ours':>11}")
    for name in ARMS:
        world, group, tool = arm(name)
        cases = problems(world, group, tool, args.targets, args.seed + sum(map(ord, name)))
        ours, ours_time = timed(run_ours, world, group, tool, cases)
        pink, pink_time = timed(run_pink, world, group, tool, cases)
        reached = sum(o.reached for o in ours), sum(o.reached for o in pink)
        ratio = reached[1] / reached[0] if reached[0] else float("inf")
        print(f"{name:<18}{group.dofs:>5}{reached[0]:>4}/{args.targets:<2}"
              f"{reached[1]:>4}/{args.targets:<2}"
              f"{sum(o.violations for o in ours):>11}{sum(o.violations for o in pink):>11}"
              f"{str(all(o.finite for o in ours + pink)):>8}{ours_time * 1e3:>9.1f}"
              f"{pink_time * 1e3:>9.1f}{ratio:>10.2f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
