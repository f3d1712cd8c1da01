"""Campaign throughput on this machine: a 50-job campaign run serially in this process
and on 2 worker processes, the two interleaved round after round.

For each engine: the start-up (workers started, package imported, mission loaded),
the sweep's wall time, and the per-job overhead: the wall time a job occupies a
worker (sweep wall time x workers / jobs) minus the job's own run time (its
``wall_time`` column, measured where it ran), as a share of that run time. The
speed-up of 2 workers over serial is given without and with the start-ups, and the
CPU time the jobs' processes got per second of sweep ("cores": other processes on a
shared machine leave fewer than 2). The rows of both engines are compared, wall times
aside.

The jobs are missions/pickup.campaign.yaml's (the part moved on the workbench, noisy
start posture) with each run's mission time capped, so that a round takes a minute.

    python bench/sweep.py                       # 50 jobs, 3 s of mission time each
    python bench/sweep.py --samples 20 --duration 10 --rounds 3
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

import psutil
import yaml

from robocop_dsl.campaign import comparable, load_campaign, open_engine, results_table, sweep
from robocop_dsl.campaign.worker import PROCESS_CACHE, WorkerCache, prepare

CAMPAIGN = Path(__file__).resolve().parent.parent / "missions" / "pickup.campaign.yaml"
WORKERS = 2


def bench_campaign(folder: Path, samples: int, duration: float) -> Path:
    """A copy of the pickup campaign with ``samples`` samples, missions found from
    anywhere and each run capped at ``duration`` [s] of mission time."""
    data = yaml.safe_load(CAMPAIGN.read_text(encoding="utf-8"))
    data["samples"] = samples
    data["missions"] = [str(CAMPAIGN.parent / m) for m in data["missions"]]
    data["duration"] = duration
    path = folder / "bench.campaign.yaml"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    return path


def timed_sweep(campaign, **options) -> dict:
    """One sweep on a fresh ``open_engine(**options)``: ``startup`` and ``sweep`` [s],
    the ``cpu`` time [s] its jobs' processes got meanwhile, the mean ``run`` [s] of a
    job where it ran, and the rows."""
    PROCESS_CACHE.clear()  # the serial engine loads the mission as the workers do
    with open_engine(loads=campaign.loads, **options) as engine:
        cpu = cpu_time(engine)
        started = time.perf_counter()
        rows, _ = sweep(campaign, engine)
        seconds = time.perf_counter() - started
        cpu = cpu_time(engine) - cpu
    return {"startup": engine.startup, "sweep": seconds, "rows": rows, "cpu": cpu,
            "run": statistics.fmean(row["wall_time"] for row in rows)}


def cpu_time(engine) -> float:
    """CPU time [s] used so far by the engine's workers, or by this process."""
    if not hasattr(engine, "pids"):
        return time.process_time()
    return sum(sum(psutil.Process(pid).cpu_times()[:2]) for pid in engine.pids)


def preparing(campaign) -> float:
    """Mean wall time [s] to draw a job's conditions and build its runner, the part of
    a job's ``wall_time`` that is not the mission run."""
    cache = WorkerCache()
    cache.preload(campaign.loads)
    started = time.perf_counter()
    for job in campaign.jobs:
        prepare(job, cache)
    return (time.perf_counter() - started) / len(campaign.jobs)


def differences(rows: list, others: list) -> str:
    """``identical``, or how many jobs' rows differ, in which columns, and the first
    one's outcomes and messages."""
    table, other = (comparable(results_table(r)).to_pylist() for r in (rows, others))
    differing = [(a, b) for a, b in zip(table, other) if a != b]
    if not differing and len(table) == len(other):
        return "identical"
    columns = sorted({k for a, b in differing for k in a.keys() | b.keys() if a.get(k) != b.get(k)})
    a, b = differing[0]
    return (f"DIFFER in {len(differing)} jobs, columns {', '.join(columns)}; job {a['job']}: "
            f"{a['outcome']} ({a['message']}) against {b['outcome']} ({b['message']})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=50, help="jobs in the campaign")
    parser.add_argument("--duration", type=float, default=3.0,
                        help="mission-time cap per run [s]")
    parser.add_argument("--rounds", type=int, default=2,
                        help="serial and 2-worker sweeps, interleaved")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        campaign = load_campaign(bench_campaign(Path(folder), args.samples, args.duration))
    jobs = len(campaign.jobs)
    print(f"{jobs} jobs of {CAMPAIGN.name}, mission time capped at {args.duration:g} s; "
          f"{args.rounds} rounds, serial and {WORKERS} workers interleaved; "
          f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
    engines = {"serial": {"serial": True}, f"{WORKERS} workers": {"workers": WORKERS}}
    results: dict = {name: [] for name in engines}
    for round_ in range(args.rounds):
        order = list(engines) if round_ % 2 == 0 else list(reversed(engines))
        for name in order:
            results[name].append(timed_sweep(campaign, **engines[name]))
    prepare_time = preparing(campaign)

    print(f"\n{'':<12}{'start-up':>10}{'sweep':>9}{'jobs/s':>8}{'slot/job':>10}"
          f"{'run/job':>9}{'overhead':>10}{'cores':>7}")
    best, startup = {}, {}
    for name, runs in results.items():
        workers = 1 if name == "serial" else WORKERS
        run = best[name] = min(runs, key=lambda r: r["sweep"])
        startup[name] = runs[0]["startup"]  # the first: a fresh process's
        slot = run["sweep"] * workers / jobs
        print(f"{name:<12}{startup[name]:>9.2f}s{run['sweep']:>8.2f}s"
              f"{jobs / run['sweep']:>8.2f}{slot:>9.3f}s{run['run']:>8.3f}s"
              f"{(slot / run['run'] - 1) * 100:>9.1f}%{run['cpu'] / run['sweep']:>7.2f}")
    pool_name = f"{WORKERS} workers"
    serial, pool = best["serial"], best[pool_name]
    ratios = [s["sweep"] / p["sweep"] for s, p in zip(results["serial"], results[pool_name])]
    print(f"\nstart-up: the first round's (later rounds reuse the fork server: "
          f"{min(r['startup'] for r in results[pool_name]):.2f}s); sweep: the best round")
    print(f"speed-up of {WORKERS} workers over serial: {serial['sweep'] / pool['sweep']:.2f}x "
          f"(per round {', '.join(f'{r:.2f}x' for r in ratios)}), "
          f"{(startup['serial'] + serial['sweep']) / (startup[pool_name] + pool['sweep']):.2f}x "
          f"with the start-ups")
    per_job = {name: run["cpu"] / jobs for name, run in best.items()}
    print(f"CPU time per job: serial {per_job['serial']:.3f} s, {WORKERS} workers "
          f"{per_job[pool_name]:.3f} s: on {WORKERS} idle cores the workers would be "
          f"{WORKERS * per_job['serial'] / per_job[pool_name]:.2f}x serial (an estimate)")
    print(f"a job's run includes {prepare_time * 1e3:.1f} ms of drawing its conditions and "
          f"building its runner ({prepare_time / serial['run'] * 100:.1f} % of it)")
    reference = results["serial"][0]["rows"]
    for name, runs in results.items():
        for round_, run in enumerate(runs):
            if run["rows"] is not reference:
                print(f"rows of {name}, round {round_ + 1}, against serial round 1 "
                      f"(wall_time aside): {differences(reference, run['rows'])}")
    print(f"load average at the end: {os.getloadavg()[0]:.1f}; 'cores': the CPU time the "
          f"jobs' processes got over the sweep's wall time (below {WORKERS} when other "
          f"processes share the cores, which lowers the speed-up)")


if __name__ == "__main__":
    main()
