"""``robocop-mission sweep CAMPAIGN.yaml``: run a campaign and tabulate it.

The jobs run on worker processes of this machine (``--workers``), on the workers of a
running Dask scheduler (``--scheduler``) or in this process (``--serial``); the
workers start once and load the campaign's missions before the first job.

Exit codes: 0 every job succeeded, 1 some job did not (or the table could not be
written), 2 invalid campaign, mission or output (nothing ran) or no engine to run on,
130 interrupted (Ctrl-C), 143 terminated (SIGTERM); the finished jobs are written.
"""

from __future__ import annotations

import os
import signal
import sys
import time
from contextlib import ExitStack
from pathlib import Path

from ..diagnostics import DiagnosticError, render_all
from .stop_signals import StopSignals


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "sweep", help="run a campaign: missions x world variants x random conditions",
        description="Check every mission of a campaign, run all its jobs headless on "
                    "worker processes and write one row per job to a Parquet table.")
    parser.add_argument("campaign", help="the campaign file (.campaign.yaml)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N",
                       help="worker processes on this machine (default: one per CPU; "
                            "never more than the CPUs this process may use, nor jobs)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on a running Dask scheduler, e.g. tcp://10.0.0.5:8786")
    where.add_argument("--serial", action="store_true",
                       help="run the jobs one by one in this process")
    parser.add_argument("--output", "-o", metavar="FILE.parquet",
                        help="results table (default: CAMPAIGN_NAME.results.parquet here); "
                             "a results table there is replaced, any other file kept")
    parser.add_argument("--replace", action="store_true",
                        help="write over the output file even when it is not a results "
                             "table")
    parser.add_argument("--format", choices=("text", "json", "github"), default="text",
                        help="how to print diagnostics")
    parser.set_defaults(command=run)


def run(args) -> int:
    with SweepStopSignals() as signals:
        try:
            return _sweep(args, signals)
        except KeyboardInterrupt:
            return 128 + (signals.received or signal.SIGINT)


def _sweep(args, signals) -> int:
    from ..campaign import OutputError, WorkerStartError, check_output, load_campaign, \
        open_engine, results_table, sweep, write_results
    from rich.console import Console
    from rich.markup import escape

    from ..campaign.summary import print_summary
    from .sweep_progress import SweepProgress

    problem = _usage_problem(args)
    if problem:
        print(f"error: {problem}", file=sys.stderr)
        return 2
    try:
        campaign = load_campaign(args.campaign)
    except DiagnosticError as error:
        print(render_all(error.diagnostics, args.format), file=sys.stderr)
        return 2
    output = Path(args.output or f"{campaign.name}.results.parquet")
    try:
        check_output(output, args.replace)
    except OutputError as error:
        print(f"error: cannot write the results to '{output}': {error}", file=sys.stderr)
        return 2
    console = Console(file=sys.stdout, highlight=False)
    started = time.perf_counter()
    with ExitStack() as stack:
        try:
            workers = min(args.workers or cpu_count(), cpu_count(), len(campaign.jobs))
            engine = stack.enter_context(open_engine(workers, args.scheduler, args.serial,
                                                     loads=campaign.loads))
        except (OSError, ValueError) as error:
            where = "reach the Dask scheduler" if args.scheduler else "start the workers"
            print(f"error: cannot {where}: {error}", file=sys.stderr)
            return 2
        except WorkerStartError as error:
            print(f"error: {error}", file=sys.stderr)
            return 2
        console.print(f"{escape(campaign.name)}: {len(campaign.jobs)} jobs on "
                      f"{escape(engine.description)}")
        with SweepProgress(len(campaign.jobs)) as progress:
            rows, interrupted = sweep(campaign, engine, on_row=progress.update)
            signals.armed = False
    metadata = {"campaign": campaign.name, "campaign_file": campaign.path,
                "seed": campaign.spec.seed, "samples": campaign.spec.samples}
    table = results_table(rows, metadata)
    try:
        write_results(table, output)
    except OSError as error:
        print(f"error: cannot write the results to '{output}': {error}", file=sys.stderr)
        return 1
    print_summary(table, campaign, console, args.campaign)
    console.print(f"{len(rows)} of {len(campaign.jobs)} jobs in "
                  f"{time.perf_counter() - started:.1f} s; results: {escape(str(output))}")
    if interrupted or signals.received is not None:
        return 128 + (signals.received or signal.SIGINT)
    return 0 if all(row["outcome"] == "success" for row in rows) else 1


def _usage_problem(args) -> str | None:
    """What is wrong with the options, or ``None``."""
    if args.workers is not None and args.workers < 1:
        return "--workers must be at least 1"
    if args.scheduler is not None and not args.scheduler.strip():
        return "--scheduler needs an address, e.g. tcp://10.0.0.5:8786"
    if args.output is not None and not args.output.strip():
        return "--output needs a file name, e.g. results.parquet"
    return None


def cpu_count() -> int:
    """The CPUs this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


class SweepStopSignals(StopSignals):
    """The first SIGINT or SIGTERM, while ``armed``, raises ``KeyboardInterrupt``
    (which stops the sweep).

    Attributes:
        armed: Whether a signal raises; cleared once the sweep ended, so that the
            finished jobs are written whatever comes.
    """

    def __init__(self):
        super().__init__()
        self.armed = True

    def stop(self) -> None:
        if self.armed:
            raise KeyboardInterrupt
