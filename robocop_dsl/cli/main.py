"""Entry point: ``robocop-mission COMMAND ...``.

Exit codes: 0 success; 1 errors in the input or a failure outcome; 2 usage error or
invalid mission (``run``); 3 run-time fault; 130 interrupted; 141 output closed early
(``robocop-mission world ... | head``: quietly, as Unix tools do).

Only the standard library and the light command modules are imported here: each command
imports what it needs (pinocchio, networkx, matplotlib...) when it runs, so that
``--help`` and ``--version`` answer at once.
"""

from __future__ import annotations

import argparse
import os
import sys

from .. import __version__
from . import (check_cmd, export_cmd, graph_cmd, lsp_cmd, plot_cmd, run_cmd, sweep_cmd,
               world_cmd)

BROKEN_PIPE = 128 + 13   # exit code of a process whose output pipe closed (SIGPIPE)
INTERRUPTED = 128 + 2    # exit code of a process stopped by Ctrl-C (SIGINT)
COMMANDS = (check_cmd, run_cmd, graph_cmd, world_cmd, plot_cmd, export_cmd, sweep_cmd,
            lsp_cmd)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="robocop-mission",
        description="Check, run and inspect robot missions written for RoboCoP-style worlds.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    subparsers = parser.add_subparsers(dest="name", required=True, metavar="COMMAND")
    for command in COMMANDS:
        command.add_parser(subparsers)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run one command; return its exit code. Without arguments, print the help on
    stderr and return 2 (a usage error)."""
    parser = build_parser()
    arguments = sys.argv[1:] if argv is None else argv
    if not arguments:
        parser.print_help(sys.stderr)
        return 2
    try:
        args = parser.parse_args(argv)
    except SystemExit as exit_:
        return int(exit_.code or 0)
    return args.command(args)


def entry_point() -> None:
    """The ``robocop-mission`` command: :func:`main`; when the reader of its output
    goes away (a pipe into ``head``), exit 141 without a word, and on a Ctrl-C that no
    command handles yet (while it imports what it needs), 130."""
    try:
        code = main()
        sys.stdout.flush()
    except BrokenPipeError:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        code = BROKEN_PIPE
    except KeyboardInterrupt:
        code = INTERRUPTED
    sys.exit(code)
