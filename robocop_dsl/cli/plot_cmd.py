"""``robocop-mission plot LOG``: PNG or SVG figures of a logged run: one panel per joint
group or per error dimension, the states in a strip with one row per machine."""

from __future__ import annotations

import sys


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "plot", help="plot a run logged with 'run --log DIR'",
        description="Write joint positions, velocity commands (one panel per joint "
                    "group), task errors (one panel per unit) and, with force sensors, "
                    "forces (one panel per sensor) as PNG or SVG figures, under a strip "
                    "of the states with one row per machine.")
    parser.add_argument("log", help="the folder given to 'run --log'")
    parser.add_argument("--output", "-o", help="folder for the figures (default: LOG)")
    parser.add_argument("--format", choices=("png", "svg"), default="png",
                        help="image format (default png)")
    parser.set_defaults(command=run)


def run(args) -> int:
    from ..runtime.log import TIMESERIES, UnreadableLog
    from ..runtime.plot import PlotError, plot_run

    try:
        paths = plot_run(args.log, args.output, args.format)
    except FileNotFoundError:
        print(f"{args.log}: no {TIMESERIES} here; write one with "
              f"'robocop-mission run MISSION --log {args.log}'", file=sys.stderr)
        return 1
    except (UnreadableLog, PlotError) as error:
        print(f"robocop-mission plot: error: {error}", file=sys.stderr)
        return 1
    for path in paths:
        print(path)
    return 0
