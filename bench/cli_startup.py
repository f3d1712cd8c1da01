"""How long ``robocop-mission`` takes to answer ``--help``, ``--version`` and each
command's ``--help``, against ``python -c pass`` in the same process and the same loop.

Each run is a fresh interpreter started the way the ``robocop-mission`` script starts
one (``python -m robocop_dsl``). Prints, per command line, the median and best wall
time of ``--runs`` runs and the ratio of the median to ``python -c pass``'s.

    python bench/cli_startup.py [--runs 10]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
COMMANDS = ("check", "run", "graph", "world", "plot", "sweep")
LINES = [("python -c pass", ["-c", "pass"]),
         ("robocop-mission", ["-m", "robocop_dsl"]),
         ("robocop-mission --version", ["-m", "robocop_dsl", "--version"]),
         ("robocop-mission --help", ["-m", "robocop_dsl", "--help"])]
LINES += [(f"robocop-mission {c} --help", ["-m", "robocop_dsl", c, "--help"])
          for c in COMMANDS]


def wall_times(arguments: list, runs: int) -> list:
    """Wall-clock seconds of ``runs`` runs of ``python ARGUMENTS``."""
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run([sys.executable, *arguments], cwd=REPO, capture_output=True,
                       check=False)
        times.append(time.perf_counter() - start)
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=10)
    args = parser.parse_args()
    results = [(label, wall_times(arguments, args.runs)) for label, arguments in LINES]
    baseline = statistics.median(results[0][1])
    print(f"{'command line':<32} {'median [s]':>10} {'best [s]':>9} {'ratio':>6}")
    for label, times in results:
        median = statistics.median(times)
        print(f"{label:<32} {median:>10.3f} {min(times):>9.3f} {median / baseline:>6.2f}")


if __name__ == "__main__":
    main()
