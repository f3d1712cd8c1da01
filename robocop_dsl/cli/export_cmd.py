"""``robocop-mission export LOG --mcap``: a logged run's folder (events and time series)
as ``run.mcap``, ROS 2 messages on the topics a run writes, for logs written without it
or before it existed.

Exit codes: 0 written, 1 no log there, a damaged one, no world, a world that does not
load, or an output that exists or cannot be written, 2 usage.
"""

from __future__ import annotations

import sys

from ..diagnostics import DiagnosticError, render_all


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "export", help="convert a run logged with 'run --log DIR' (e.g. to MCAP)",
        description="Convert a logged run (events.jsonl and the time series) to an MCAP "
                    "file of ROS 2 messages, as 'run --log' writes run.mcap: for "
                    "Foxglove, PlotJuggler, 'ros2 bag' and rosbags.")
    parser.add_argument("log", help="the folder given to 'run --log'")
    parser.add_argument("--mcap", action="store_true", required=True,
                        help="write an MCAP file (the only format)")
    parser.add_argument("--output", "-o", metavar="FILE",
                        help="where to write it (default: LOG/run.mcap)")
    parser.add_argument("--replace", action="store_true",
                        help="write over the output file when it exists (a run's own "
                             "run.mcap has targets an export cannot rebuild)")
    parser.add_argument("--world", metavar="WORLD.yaml",
                        help="the run's world, for logs that do not name it")
    parser.set_defaults(command=run)


def run(args) -> int:
    from ..ecosystem import ExportError, export_mcap
    from ..runtime.log import UnreadableLog

    try:
        world = None
        if args.world is not None:
            from ..world import load_world

            world = load_world(args.world)
        path = export_mcap(args.log, args.output, world, args.replace)
    except DiagnosticError as error:
        print(render_all(error.diagnostics), file=sys.stderr)
        return 1
    except (ExportError, UnreadableLog) as error:
        print(f"robocop-mission export: error: {error}", file=sys.stderr)
        return 1
    print(path)
    return 0
