"""``robocop-mission sweep CAMPAIGN.yaml``: run a campaign and tabulate it.

The jobs run on worker processes of this machine (``--workers``), on the workers of a
running Dask scheduler (``--scheduler``) or in this process (``--serial``); the
workers start once and load the campaign's missions before the first job.

Exit codes: 0 every job succeeded, 1 some job did not, 2 invalid campaign or mission
(nothing ran) or no engine to run on, 130 interrupted (the finished jobs are written).
"""

from __future__ import annotations

import os
import sys
import time
from contextlib import ExitStack
from pathlib import Path

from ..diagnostics import DiagnosticError, render_all


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "sweep", help="run a campaign: missions x world variants x random conditions",
        description="Check every mission of a campaign, run all its jobs headless on "
                    "worker processes and write one row per job to a Parquet table.")
    parser.add_argument("campaign", help="the campaign file (.campaign.yaml)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N",
                       help="worker processes on this machine (default: one per CPU; "
                            "never more than jobs)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on a running Dask scheduler, e.g. tcp://10.0.0.5:8786")
    where.add_argument("--serial", action="store_true",
                       help="run the jobs one by one in this process")
    parser.add_argument("--output", "-o", metavar="FILE.parquet",
                        help="results table (default: CAMPAIGN_NAME.results.parquet here)")
    parser.add_argument("--format", choices=("text", "json", "github"), default="text",
                        help="how to print diagnostics")
    parser.set_defaults(command=run)


def run(args) -> int:
    from ..campaign import WorkerStartError, load_campaign, open_engine, results_table, \
        sweep, write_results
    from rich.console import Console

    from ..campaign.summary import print_summary
    from .sweep_progress import SweepProgress

    if args.workers is not None and args.workers < 1:
        print("error: --workers must be at least 1", file=sys.stderr)
        return 2
    try:
        campaign = load_campaign(args.campaign)
    except DiagnosticError as error:
        print(render_all(error.diagnostics, args.format), file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    console = Console(file=sys.stdout, highlight=False)
    output = Path(args.output or f"{campaign.name}.results.parquet")
    started = time.perf_counter()
    with ExitStack() as stack:
        try:
            workers = min(args.workers or os.cpu_count() or 1, len(campaign.jobs))
            engine = stack.enter_context(open_engine(workers, args.scheduler, args.serial,
                                                     loads=campaign.loads))
        except OSError as error:
            where = "reach the Dask scheduler" if args.scheduler else "start the workers"
            print(f"error: cannot {where}: {error}", file=sys.stderr)
            return 2
        except WorkerStartError as error:
            print(f"error: {error}", file=sys.stderr)
            return 2
        except KeyboardInterrupt:
            return 130
        console.print(f"{campaign.name}: {len(campaign.jobs)} jobs on {engine.description}")
        with SweepProgress(len(campaign.jobs)) as progress:
            rows, interrupted = sweep(campaign, engine, on_row=progress.update)
    metadata = {"campaign": campaign.name, "campaign_file": campaign.path,
                "seed": campaign.spec.seed, "samples": campaign.spec.samples}
    table = results_table(rows, metadata)
    write_results(table, output)
    print_summary(table, campaign, console, args.campaign)
    console.print(f"{len(rows)} of {len(campaign.jobs)} jobs in "
                  f"{time.perf_counter() - started:.1f} s; results: {output}")
    if interrupted:
        return 130
    return 0 if all(row["outcome"] == "success" for row in rows) else 1

