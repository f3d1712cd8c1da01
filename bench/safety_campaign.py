"""A randomised safety campaign: missions written to break the safety layer (see
``tests/safety_missions.py``) run on BAZAR and the Panda, and the controller's promises
recomputed from each run's log.

The table gives, per robot and in all: runs and their outcomes, runs breaking each
promise (positions past a limit by more than 1 mrad, collision pairs closer than
``min_distance`` - 1 mm, velocity commands over their limit, accelerations over
their limit in a cycle with no ``constraint_relaxed`` event, non-finite values), the
worst figures over the runs, the events that say the controller could not do as asked
(count of events, and of runs with one) and the largest cycle compute time over the
run's median. Below it, the runs that broke a promise or exited with a code other than
0 or 1 (a fault), by robot and seed, with their worst sample: run one again with
``--robot ROBOT --seed SEED --runs 1``.

Usage: python bench/safety_campaign.py [--runs 200] [--seed 0] [--robot both]
       [--workers 2]
"""

from __future__ import annotations

import argparse
import contextlib
import io
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from robocop_dsl.cli.main import main as cli

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

from safety_missions import COUNTED_EVENTS, RunFigures, check_run, safety_case  # noqa: E402

KINDS = ("position", "clearance", "velocity", "acceleration", "non_finite")
OUTCOMES = ("success", "failure", "stopped", "fault")
ROWS = (["runs", "outcomes", "faults after a relaxation, no handler",
         "other exit codes than 0 or 1"]
        + [f"runs breaking: {kind}" for kind in KINDS[:3]]
        + ["runs breaking: acceleration, unannounced", "runs breaking: non-finite values",
           "worst position excess [mrad]", "smallest clearance margin [mm]",
           "worst velocity excess [%]", "worst acceleration excess, relaxed included [%]"]
        + [f"{kind} events (runs)" for kind in COUNTED_EVENTS]
        + ["compute max / median: worst run (median run)"])


def run_case(job: tuple[str, int]) -> tuple[str, int, int, RunFigures, bool]:
    """Run the mission of ``job`` (robot, seed) through the command line; return the
    robot, the seed, the exit code, the run's figures and whether a fault is the
    mission's due (:meth:`SafetyCase.fault_expected`)."""
    robot, seed = job
    case = safety_case(robot, seed)
    with tempfile.TemporaryDirectory() as folder:
        path = case.write(folder)
        with contextlib.redirect_stdout(io.StringIO()), \
                contextlib.redirect_stderr(io.StringIO()):
            code = cli(["run", str(path), "--log", str(Path(folder) / "log")])
        figures = check_run(Path(folder) / "log", case.limits)
        return robot, seed, code, figures, case.fault_expected(figures)


def _events(runs: list, kind: str) -> str:
    return f"{sum(f.events[kind] for f in runs)} ({sum(f.events[kind] > 0 for f in runs)})"


def column(results: list) -> list[str]:
    """One column of the table: the figures of ``results``."""
    runs = [figures for _, _, _, figures, _ in results]
    if not runs:
        return [""] * len(ROWS)
    margins = [m for f in runs for m in f.clearance_margin.values()]
    outcomes = " ".join(f"{o} {sum(f.outcome == o for f in runs)}" for o in OUTCOMES
                        if any(f.outcome == o for f in runs))
    due = [code == 3 and expected for _, _, code, _, expected in results]
    return ([str(len(runs)), outcomes, str(sum(due)),
             str(sum(code not in (0, 1) and not d for (_, _, code, _, _), d
                     in zip(results, due)))]
            + [str(sum(kind in f.violations for f in runs)) for kind in KINDS]
            + [f"{max(f.position_excess for f in runs) * 1e3:.3f}",
               f"{min(margins) * 1e3:.2f}" if margins else "-",
               f"{max(f.velocity_excess for f in runs) * 100:.3g}",
               f"{max(f.acceleration_excess for f in runs) * 100:.3g}"]
            + [_events(runs, kind) for kind in COUNTED_EVENTS]
            + [f"{max(f.compute_ratio for f in runs):.0f} "
               f"({np.median([f.compute_ratio for f in runs]):.0f})"])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=200)
    parser.add_argument("--seed", type=int, default=0, help="seed of the first run")
    parser.add_argument("--robot", choices=("bazar", "panda", "both"), default="both",
                        help="both: the robots in turn, each from --seed on")
    parser.add_argument("--workers", type=int, default=2, help="processes running missions")
    args = parser.parse_args(argv)
    robots = ("bazar", "panda") if args.robot == "both" else (args.robot,)
    jobs = [(robots[i % len(robots)], args.seed + i // len(robots)) for i in range(args.runs)]
    started = time.perf_counter()
    if args.workers > 1:
        with ProcessPoolExecutor(args.workers) as pool:
            results = list(pool.map(run_case, jobs))
    else:
        results = [run_case(job) for job in jobs]
    results.sort(key=lambda result: (result[0], result[1]))
    table = Table(title=f"Safety campaign: {args.runs} runs from seed {args.seed} "
                        f"({time.perf_counter() - started:.0f} s)")
    table.add_column("")
    groups = {robot: [r for r in results if r[0] == robot] for robot in robots}
    if len(robots) > 1:
        groups["all"] = results
    for name in groups:
        table.add_column(name, justify="right")
    for row, values in zip(ROWS, zip(*(column(group) for group in groups.values()))):
        table.add_row(escape(row), *values)
    console = Console(width=140)
    console.print(table)
    broken = [r for r in results
              if r[3].violations or r[2] not in (0, 1) and not (r[2] == 3 and r[4])]
    for robot, seed, code, figures, _ in broken:
        broke = [f"{kind} {figures.worst[kind]}" for kind in figures.violations]
        console.print("; ".join([f"{robot} seed {seed}: exit {code}, outcome {figures.outcome}"]
                                + broke), highlight=False, markup=False)
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
