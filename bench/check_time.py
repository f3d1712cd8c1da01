"""Time ``robocop-mission check missions/pickup.mission`` from the shell.

Each run is a fresh interpreter, so the figure includes Python's start, the imports,
building the parser, loading the world and checking. Prints the best and median of
``--runs`` wall-clock times in seconds, and the median CPU time (user + system) of the
child process, which a busy machine disturbs less.

    python bench/check_time.py [--runs 10] [MISSION]
"""

from __future__ import annotations

import argparse
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
# What the ``robocop-mission`` script that pip installs runs.
COMMAND = ("import sys\n"
           "from robocop_dsl.cli.main import entry_point\n"
           "sys.argv[0] = 'robocop-mission'\n"
           "sys.exit(entry_point())\n")


def _child_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def time_check(mission: Path, runs: int) -> tuple[list[float], list[float]]:
    """Wall-clock and CPU seconds of ``runs`` checks, each in a new process."""
    walls, cpus = [], []
    for _ in range(runs):
        cpu, start = _child_cpu(), time.perf_counter()
        done = subprocess.run([sys.executable, "-c", COMMAND, "check", str(mission)],
                              cwd=REPO, capture_output=True, text=True)
        walls.append(time.perf_counter() - start)
        cpus.append(_child_cpu() - cpu)
        if done.returncode != 0:
            sys.exit(f"check failed ({done.returncode}):\n{done.stdout}{done.stderr}")
    return walls, cpus


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mission", nargs="?", default=REPO / "missions" / "pickup.mission",
                        type=Path)
    parser.add_argument("--runs", type=int, default=10)
    args = parser.parse_args()
    walls, cpus = time_check(args.mission, args.runs)
    print(f"check {args.mission.name}: wall best {min(walls):.3f} s, median "
          f"{statistics.median(walls):.3f} s; CPU median {statistics.median(cpus):.3f} s "
          f"({len(walls)} runs)")


if __name__ == "__main__":
    main()
