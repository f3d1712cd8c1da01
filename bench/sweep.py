"""Campaign throughput on this machine: jobs per second run serially and on a local
Dask cluster of 2 worker processes, and the per-job overhead of the campaign engine
over a bare run of the same missions.

A bare run is what ``robocop-mission run`` does for one job: make the runner of an
already loaded mission with the job's conditions and run it. The engine adds, per job,
drawing the conditions, the observers that fill the results table, the budget thread
and, on Dask, scheduling and moving the row back.

    python bench/sweep.py                  # 10 samples of missions/pickup.campaign.yaml
    python bench/sweep.py --samples 16 --duration 10
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import yaml

from robocop_dsl.campaign import load_campaign, open_engine, sweep
from robocop_dsl.campaign.sampling import draw_conditions
from robocop_dsl.campaign.worker import WorkerCache

CAMPAIGN = Path(__file__).resolve().parent.parent / "missions" / "pickup.campaign.yaml"


def bench_campaign(folder: Path, samples: int, duration: float | None) -> Path:
    """A copy of the pickup campaign with ``samples`` samples and missions found from
    anywhere; ``duration`` [s] caps each run's mission time."""
    data = yaml.safe_load(CAMPAIGN.read_text(encoding="utf-8"))
    data["samples"] = samples
    data["missions"] = [str(CAMPAIGN.parent / m) for m in data["missions"]]
    if duration is not None:
        data["duration"] = duration
    path = folder / "bench.campaign.yaml"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    return path


def bare(campaign, repeats: int = 2) -> float:
    """Wall time [s] of the jobs' bare runs (missions and worlds loaded beforehand); the
    best of ``repeats`` passes, the first one warming up the libraries."""
    cache = WorkerCache()
    prepared = []
    for job in campaign.jobs:
        mission = cache.mission(job.mission, job.world)
        prepared.append((job, mission, draw_conditions(job, cache.world(job.world))))
    best = float("inf")
    for _ in range(repeats):
        started = time.perf_counter()
        for job, mission, conditions in prepared:
            runner = mission.runner(
                solver=job.setting("solver"), hierarchy=job.setting("hierarchy"),
                time_step=job.setting("time_step"), initial=conditions.initial,
                body_placements=conditions.body_placements or None)
            runner.run(duration=job.duration)
        best = min(best, time.perf_counter() - started)
    return best


def engine(campaign, **options) -> tuple:
    """``(startup, sweep)`` wall times [s] on the engine ``open_engine(**options)``; the
    sweep is run once to warm the workers' caches, then timed."""
    started = time.perf_counter()
    with open_engine(**options) as chosen:
        ready = time.perf_counter()
        sweep(campaign, chosen)
        warm = time.perf_counter()
        rows, _ = sweep(campaign, chosen)
        finished = time.perf_counter()
    outcomes = {row["outcome"] for row in rows}
    print(f"  {chosen.description}: outcomes {sorted(outcomes)}, first sweep "
          f"{warm - ready:.2f} s (cold caches)")
    return ready - started, finished - warm


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=10)
    parser.add_argument("--duration", type=float, help="mission-time cap per run [s]")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        campaign = load_campaign(bench_campaign(Path(folder), args.samples, args.duration))
    jobs = len(campaign.jobs)
    print(f"{jobs} jobs of {CAMPAIGN.name}")
    bare_time = bare(campaign)
    _, serial_time = engine(campaign, serial=True)
    startup, local_time = engine(campaign, workers=2)
    print(f"\n{'':<28}{'jobs/s':>10}{'s/job':>10}")
    for name, seconds in (("bare runs", bare_time), ("serial engine", serial_time),
                          ("local cluster, 2 workers", local_time)):
        print(f"{name:<28}{jobs / seconds:>10.2f}{seconds / jobs:>10.3f}")
    print(f"\nengine overhead per job, serial: {(serial_time - bare_time) / jobs * 1e3:.1f} ms "
          f"({(serial_time / bare_time - 1) * 100:.1f} % of a bare run)")
    print(f"speed-up of 2 local workers over serial: {serial_time / local_time:.2f}x "
          f"(cluster start-up {startup:.2f} s, not included)")


if __name__ == "__main__":
    main()
