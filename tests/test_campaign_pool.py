"""Worker processes of this machine: started once, each loads the mission once and runs
many jobs, gives the serial rows job for job, survives a worker killed mid-job and
stops its workers when the sweep is interrupted."""

import os
import signal

import psutil
import pytest

from robocop_dsl.campaign import load_campaign, open_engine, run_job, sweep
from robocop_dsl.campaign.worker import PROCESS_CACHE

from conftest import MISSIONS
from test_campaign_engine import small_campaign

JOBS = 6


def run_and_count(job):
    """The job's row, with the worker's pid and how many worlds and missions it built."""
    row = run_job(job)
    return {**row, "pid": os.getpid(), "world_loads": PROCESS_CACHE.built["world"],
            "mission_loads": PROCESS_CACHE.built["mission"]}


def run_or_die(job):
    """Job 1 kills the worker running it, every time it is sent."""
    if job.index == 1:
        os.kill(os.getpid(), signal.SIGKILL)
    return run_job(job)


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    """Six pickup jobs, the part moved and the start posture noisy, capped at 1 s."""
    path = small_campaign(tmp_path_factory.mktemp("pool"), [str(MISSIONS / "pickup.mission")],
                          samples=JOBS, extra="duration: 1 s\n")
    return load_campaign(path)


@pytest.fixture(scope="module")
def serial_rows(campaign):
    with open_engine(serial=True, loads=campaign.loads) as engine:
        rows, interrupted = sweep(campaign, engine)
    assert not interrupted
    return _by_job(rows)


def _by_job(rows) -> dict:
    """Each row without its wall time (the one column that varies), by job."""
    return {row["job"]: {k: v for k, v in row.items() if k != "wall_time"} for row in rows}


def test_two_workers_give_the_serial_rows(campaign, serial_rows):
    """Same outcome, state, cycles, errors, margins and conditions for every job."""
    with open_engine(workers=2, loads=campaign.loads) as engine:
        rows, interrupted = sweep(campaign, engine)
    assert not interrupted and engine.startup > 0
    assert _by_job(rows) == serial_rows
    assert sorted(serial_rows) == list(range(JOBS))
    assert {r["outcome"] for r in serial_rows.values()} == {"stopped"}
    assert all(r["mission_time"] >= 1 and r["cycles"] >= 200 for r in serial_rows.values())
    assert len({r["pickup_point.x"] for r in serial_rows.values()}) == JOBS


def test_a_worker_loads_the_mission_once_and_runs_several_jobs(campaign, serial_rows):
    """Six jobs on two workers: one worker runs at least three, each built its world
    and mission once, before its first job."""
    with open_engine(workers=2, loads=campaign.loads) as engine:
        rows, _ = sweep(campaign, engine, execute=run_and_count)
    jobs_by_worker = {}
    for row in rows:
        jobs_by_worker.setdefault(row["pid"], []).append(row["job"])
    assert max(len(jobs) for jobs in jobs_by_worker.values()) >= JOBS // 2
    assert os.getpid() not in jobs_by_worker
    assert {(r["world_loads"], r["mission_loads"]) for r in rows} == {(1, 1)}
    assert {j: {k: v for k, v in r.items() if k in serial_rows[j]} for j, r in
            _by_job(rows).items()} == serial_rows


def test_a_killed_worker_costs_its_job_only(campaign, serial_rows):
    """The job whose worker dies under it, twice, is an error row; the pool is started
    again and every other job gives its serial row."""
    with open_engine(workers=2, loads=campaign.loads) as engine:
        rows, interrupted = sweep(campaign, engine, execute=run_or_die)
    rows = _by_job(rows)
    assert not interrupted and sorted(rows) == list(range(JOBS))
    assert rows[1]["outcome"] == "error"
    assert rows[1]["message"] == ("WorkerDied: its worker process died while running it, "
                                  "2 times")
    assert {j: r for j, r in rows.items() if j != 1} == {
        j: r for j, r in serial_rows.items() if j != 1}


def test_an_interrupted_sweep_stops_its_workers(campaign):
    """Ctrl-C after the first row: the rows so far are kept and no worker is left."""

    def interrupt(row):
        raise KeyboardInterrupt

    with open_engine(workers=2, loads=campaign.loads) as engine:
        workers = engine.pids
        rows, interrupted = sweep(campaign, engine, on_row=interrupt)
    assert interrupted and len(rows) == 1
    assert len(workers) == 2 and not any(psutil.pid_exists(pid) for pid in workers)
