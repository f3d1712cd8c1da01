"""``robocop-mission plot LOG``: PNG figures of a logged run, one band per state."""

from __future__ import annotations

import sys
from pathlib import Path


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "plot", help="plot a run logged with 'run --log DIR'",
        description="Write joint positions, velocity commands and task errors as PNG "
                    "figures with a coloured band per state.")
    parser.add_argument("log", help="the folder given to 'run --log'")
    parser.add_argument("--output", "-o", help="folder for the figures (default: LOG)")
    parser.set_defaults(command=run)


def run(args) -> int:
    from ..runtime.log import TIMESERIES
    from ..runtime.plot import plot_run

    if not (Path(args.log) / TIMESERIES).is_file():
        print(f"{args.log}: no {TIMESERIES} here; write one with "
              f"'robocop-mission run MISSION --log {args.log}'", file=sys.stderr)
        return 1
    for path in plot_run(args.log, args.output):
        print(path)
    return 0
