"""``robocop-mission sweep CAMPAIGN.yaml``: run a campaign on Dask and tabulate it.

Exit codes: 0 every job succeeded, 1 some job did not, 2 invalid campaign or mission
(nothing ran) or no engine to run on, 130 interrupted (the finished jobs are written).
"""

from __future__ import annotations

import sys
import time
from collections import Counter
from contextlib import ExitStack
from pathlib import Path

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, \
    TimeElapsedColumn

from ..diagnostics import DiagnosticError, render_all


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "sweep", help="run a campaign: missions x world variants x random conditions",
        description="Check every mission of a campaign, run all its jobs headless on Dask "
                    "and write one row per job to a Parquet table.")
    parser.add_argument("campaign", help="the campaign file (.campaign.yaml)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N",
                       help="worker processes of the local cluster (default: one per CPU)")
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
    from ..campaign import load_campaign, open_engine, results_table, sweep, write_results
    from ..campaign.summary import print_summary

    if args.workers is not None and args.workers < 1:
        print("error: --workers must be at least 1", file=sys.stderr)
        return 2
    try:
        campaign = load_campaign(args.campaign)
    except DiagnosticError as error:
        print(render_all(error.diagnostics, args.format), file=sys.stderr)
        return 2
    console = Console(file=sys.stdout, highlight=False)
    output = Path(args.output or f"{campaign.name}.results.parquet")
    started = time.perf_counter()
    with ExitStack() as stack:
        try:
            engine = stack.enter_context(open_engine(args.workers, args.scheduler, args.serial))
        except OSError as error:
            print(f"error: cannot reach the Dask scheduler: {error}", file=sys.stderr)
            return 2
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


class SweepProgress:
    """A progress bar with the count of each outcome (a line per tenth when not on a
    terminal)."""

    def __init__(self, total: int, stream=None):
        self.console = Console(file=stream or sys.stderr, highlight=False)
        self.total = total
        self.counts: Counter = Counter()
        self._progress = None
        self._task = None

    def __enter__(self) -> "SweepProgress":
        if self.console.is_terminal:
            self._progress = Progress(TextColumn("jobs"), BarColumn(), MofNCompleteColumn(),
                                      TimeElapsedColumn(), TextColumn("{task.description}"),
                                      console=self.console)
            self._progress.start()
            self._task = self._progress.add_task("", total=self.total)
        return self

    def __exit__(self, *exc) -> None:
        if self._progress is not None:
            self._progress.stop()

    def update(self, row: dict) -> None:
        self.counts[row["outcome"]] += 1
        done = sum(self.counts.values())
        text = "  ".join(f"{o} {n}" for o, n in sorted(self.counts.items()))
        if self._progress is not None:
            self._progress.update(self._task, completed=done, description=text)
        elif done * 10 // self.total != (done - 1) * 10 // self.total or done == self.total:
            self.console.print(f"{done}/{self.total} jobs  {text}")
