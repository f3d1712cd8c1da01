"""Time ``robocop-mission check missions/pickup.mission`` from the shell.

Each run is a fresh interpreter, so the figure includes Python's start, the imports,
building the parser, loading the world and checking. Prints the best and median of
``--runs`` wall-clock times in seconds.

    python bench/check_time.py [--runs 10] [MISSION]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
# Through the entry point when it dispatches ``check``, else the command module alone.
COMMAND = ("import sys\n"
           "from robocop_dsl.cli import main as entry\n"
           "if any(getattr(c, '__name__', '').endswith('check_cmd') for c in entry.COMMANDS):\n"
           "    sys.exit(entry.main(sys.argv[1:]))\n"
           "import argparse\n"
           "from robocop_dsl.cli import check_cmd\n"
           "parser = argparse.ArgumentParser(prog='robocop-mission')\n"
           "check_cmd.add_parser(parser.add_subparsers(dest='name', required=True))\n"
           "args = parser.parse_args(sys.argv[1:])\n"
           "sys.exit(args.command(args))\n")


def time_check(mission: Path, runs: int) -> list[float]:
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        done = subprocess.run([sys.executable, "-c", COMMAND, "check", str(mission)],
                              cwd=REPO, capture_output=True, text=True)
        times.append(time.perf_counter() - start)
        if done.returncode != 0:
            sys.exit(f"check failed ({done.returncode}):\n{done.stdout}{done.stderr}")
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mission", nargs="?", default=REPO / "missions" / "pickup.mission",
                        type=Path)
    parser.add_argument("--runs", type=int, default=10)
    args = parser.parse_args()
    times = time_check(args.mission, args.runs)
    print(f"check {args.mission.name}: best {min(times):.3f} s, "
          f"median {statistics.median(times):.3f} s over {len(times)} runs")


if __name__ == "__main__":
    main()
