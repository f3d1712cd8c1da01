"""The end-of-sweep summary: success rate per mission and variant (and per controller
setting when several were tried) with its 95 % confidence interval, then the jobs
that did not succeed with their conditions and the command that reruns each one
alone."""

from __future__ import annotations

import math
import os
import shlex
from collections import Counter
from pathlib import Path

from rich.console import Console
from rich.markup import escape
from rich.table import Table

SHOWN = 10
"""How many unsuccessful jobs the summary lists; the table has them all."""

OUTCOME_COLOURS = {"success": "green", "failure": "red", "fault": "red", "error": "red",
                   "timeout": "magenta", "stopped": "yellow", "interrupted": "yellow"}


def rerun_command(job, campaign_path: str | Path) -> str:
    """The shell command that runs ``job`` alone, with its world variant, settings and
    sampled conditions."""
    return shlex.join(["robocop-mission", "run", _shown(job.mission), "--campaign",
                       _shown(campaign_path), "--job", str(job.index)])


def _shown(path) -> str:
    """``path`` relative to the working folder when it lies under it."""
    path = Path(path).resolve()
    try:
        return os.path.relpath(path) if path.is_relative_to(Path.cwd()) else str(path)
    except ValueError:
        return str(path)


def group_key(row: dict, varied: list) -> tuple:
    return (row["mission"], row["variant"], *(row[name] for name in varied))


def print_summary(table, campaign, console: Console, campaign_path=None) -> None:
    """Print the success rates and the unsuccessful jobs of a results ``table``.

    Args:
        table: The results table (pyarrow).
        campaign: The :class:`~.jobs.Campaign` the table comes from.
        console: Where to print.
        campaign_path: The campaign file as the user named it (for the commands).
    """
    rows = table.to_pylist()
    varied = [n for n in ("solver", "hierarchy", "time_step")
              if len({row[n] for row in rows}) > 1]
    console.print(_rates(rows, varied))
    failing = [row for row in rows if row["outcome"] != "success"]
    if not failing:
        console.print(f"[green]all {len(rows)} jobs succeeded[/]")
        return
    console.print(f"\n[bold]{len(failing)} jobs did not succeed[/]")
    path = campaign_path or campaign.path
    for row in failing[:SHOWN]:
        _failure(console, row, varied, rerun_command(campaign.jobs[row["job"]], path))
    if len(failing) > SHOWN:
        console.print(f"... and {len(failing) - SHOWN} more in the results table")


def _failure(console: Console, row: dict, varied: list, command: str) -> None:
    colour = OUTCOME_COLOURS.get(row["outcome"], "white")
    settings = "".join(f", {name} {row[name]}" for name in varied)
    where = (f" in state {row['final_state']} at {row['mission_time']:.3f} s"
             if row.get("final_state") else "")
    console.print(escape(f"job {row['job']}: {row['mission']} on {row['variant']}{settings}, "
                         f"sample {row['sample']}: ") + f"[{colour}]{row['outcome']}[/]"
                  + escape(where), soft_wrap=True)
    console.print(f"  conditions: {_conditions(row)}", markup=False, soft_wrap=True)
    console.print(f"  closest limit: {_limit(row)}; worst task error at the end: "
                  f"{_number(row.get('worst_task_error'), '.6f')}", markup=False,
                  soft_wrap=True)
    if row.get("message"):
        console.print(f"  reason: {row['message']}", markup=False, soft_wrap=True)
    console.print(f"  rerun: {command}", markup=False, soft_wrap=True)


def _rates(rows: list, varied: list) -> Table:
    table = Table(title="success rate", show_edge=False)
    for column in ("mission", "variant", *varied, "jobs", "success", "95% interval",
                   "other outcomes"):
        table.add_column(column, justify="right" if column in ("jobs", "success",
                                                               "95% interval") else "left")
    groups: dict = {}
    for row in rows:
        groups.setdefault(group_key(row, varied), Counter())[row["outcome"]] += 1
    for key, counts in groups.items():
        total = sum(counts.values())
        rate = counts["success"] / total
        colour = "green" if rate == 1 else "red" if rate < 0.5 else "yellow"
        others = ", ".join(f"{n} {o}" for o, n in sorted(counts.items()) if o != "success")
        low, high = wilson_interval(counts["success"], total)
        table.add_row(*(escape(str(value)) for value in key), str(total),
                      f"[{colour}]{counts['success']} ({rate:.0%})[/]",
                      f"{low:.0%} to {high:.0%}", others or "-")
    return table


def wilson_interval(successes: int, total: int, z: float = 1.959964) -> tuple:
    """The Wilson score interval of a success rate (95 % for the default ``z``): where
    the true rate lies given ``successes`` out of ``total`` independent runs."""
    if total == 0:
        return 0.0, 1.0
    rate = successes / total
    centre = (rate + z * z / (2 * total)) / (1 + z * z / total)
    spread = z * math.sqrt(rate * (1 - rate) / total + z * z / (4 * total * total)) \
        / (1 + z * z / total)
    return max(0.0, centre - spread), min(1.0, centre + spread)


def _conditions(row: dict) -> str:
    bodies = list(dict.fromkeys(k[:-2] for k in row if k.endswith((".x", ".y", ".z"))
                                and not k.startswith("initial.")))
    text = [f"{b}=({row[b + '.x']:.3f}, {row[b + '.y']:.3f}, {row[b + '.z']:.3f})"
            for b in bodies if row.get(b + ".x") is not None]
    noisy = sum(1 for k in row if k.startswith("initial.") and row[k] is not None)
    if noisy:
        text.append(f"start posture drawn for {noisy} joints")
    if row.get("physics.friction") is not None:
        text.append(f"friction {row['physics.friction']:.3f}")
    text += [f"{k[:-len('.mass')]} {row[k]:.3f} kg" for k in row
             if k.endswith(".mass") and row[k] is not None]
    return "; ".join(text) or "-"


def _limit(row: dict) -> str:
    margin = row["min_limit_margin"]
    if margin is None or margin != margin:
        return "-"
    return f"{row['limit_joint']} at {margin:.4f} rad or m"


def _number(value, spec: str) -> str:
    return "-" if value is None or value != value else format(value, spec)
