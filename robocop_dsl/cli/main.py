"""Entry point: ``robocop-mission COMMAND ...``.

Exit codes: 0 success; 1 errors in the input or a failure outcome; 2 usage error or
invalid mission (``run``); 3 run-time fault; 130 interrupted.
"""

from __future__ import annotations

import argparse
import sys

from . import check_cmd, graph_cmd, plot_cmd, run_cmd, sweep_cmd, world_cmd

COMMANDS = (check_cmd, run_cmd, graph_cmd, world_cmd, plot_cmd, sweep_cmd)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="robocop-mission",
        description="Check, run and inspect robot missions written for RoboCoP-style worlds.")
    subparsers = parser.add_subparsers(dest="name", required=True, metavar="COMMAND")
    for command in COMMANDS:
        command.add_parser(subparsers)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run one command; return its exit code."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exit_:
        return int(exit_.code or 0)
    return args.command(args)


def entry_point() -> None:
    sys.exit(main())
