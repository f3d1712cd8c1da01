"""``robocop-mission run FILE``: run a mission headless (default) or in real time.

Exit codes: 0 success outcome, 1 failure outcome (or ``--duration`` reached first),
2 invalid mission, 3 run-time fault, 130 interrupted.
"""

from __future__ import annotations

import sys

from ..diagnostics import DiagnosticError, render_all

EXIT_CODES = {"success": 0, "failure": 1, "stopped": 1, "fault": 3, "interrupted": 130}


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "run", help="run a mission against the simulated robot",
        description="Check and run a mission. Headless and as fast as the machine goes "
                    "unless --realtime; prints progress and a summary.")
    parser.add_argument("file", help="the .mission file")
    parser.add_argument("--realtime", action="store_true",
                        help="sleep to the control period and report overruns")
    parser.add_argument("--duration", type=float, metavar="SECONDS",
                        help="stop after this much mission time")
    parser.add_argument("--solver", help="QP solver (overrides the world's controller)")
    parser.add_argument("--hierarchy", choices=("strict", "weighted"),
                        help="task hierarchy (overrides the world's controller)")
    parser.add_argument("--log", metavar="DIR", help="write events and time series to DIR")
    parser.add_argument("--campaign", metavar="CAMPAIGN.yaml",
                        help="run one job of this campaign: its world variant, controller "
                             "settings and sampled conditions (with --job)")
    parser.add_argument("--job", type=int, metavar="N",
                        help="the job to run: the 'job' column of the sweep's results table")
    parser.set_defaults(command=run)


def run(args) -> int:
    from ..runtime import RunLogger
    from .progress import ProgressDisplay, print_summary

    if (args.campaign is None) != (args.job is None):
        print("robocop-mission run: error: --campaign and --job go together", file=sys.stderr)
        return 2
    try:
        mission, runner, duration = _prepare(args)
    except DiagnosticError as error:
        print(render_all(error.diagnostics), file=sys.stderr)
        return 2
    if args.log:
        runner.add_observer(RunLogger(args.log, runner.joint_names))
    display = ProgressDisplay(mission.name)
    runner.add_observer(display)
    result = runner.run(duration=duration, realtime=args.realtime or runner.driver.realtime)
    display.close()
    print_summary(result, sys.stdout)
    if args.log:
        print(f"log: {args.log}")
    return EXIT_CODES[result.outcome]


def _prepare(args) -> tuple:
    """The mission, its runner and the mission-time cap [s]: of the file, or of a job of
    ``--campaign`` (its variant, settings and conditions; --solver/--hierarchy override)."""
    from ..runtime import load_mission

    if args.campaign is not None:
        from ..campaign.rerun import campaign_job

        job, prepared = campaign_job(args.campaign, args.job, args.file,
                                     solver=args.solver, hierarchy=args.hierarchy)
        duration = args.duration if args.duration is not None else job.duration
        return prepared.mission, prepared.runner, duration
    mission = load_mission(args.file)
    runner = mission.runner(solver=args.solver, hierarchy=args.hierarchy,
                            realtime=args.realtime)
    return mission, runner, args.duration
