"""Where jobs run: in this process, on worker processes of this machine, or on a
running Dask scheduler's workers. Every engine yields one row per job as jobs finish;
the order of the rows does not matter (the table is sorted by job).

Each engine starts its workers once and loads the campaign's missions in each before
the first job (its ``startup`` [s] says how long that took); a job then costs only its
run. On this machine the workers are :class:`~.pool.PoolEngine`'s processes, not a
local Dask cluster: its scheduler, nanny and worker processes took 1.5 to 2 s longer
to have the missions loaded, and listen on TCP ports.
"""

from __future__ import annotations

import os
import time
from contextlib import contextmanager
from typing import Callable, Iterator

from .worker import PROCESS_CACHE, failed_row, reload_process_cache, run_job

CONNECT_TIMEOUT = "20s"


class SerialEngine:
    """Runs the jobs one after the other in this process.

    Args:
        loads: ``(mission path, world path)`` pairs to load first.
    """

    description = "serial, in this process"

    def __init__(self, loads=()):
        started = time.perf_counter()
        PROCESS_CACHE.preload(loads)
        self.startup = time.perf_counter() - started

    def run(self, execute: Callable, jobs) -> Iterator[dict]:
        """Yield the row of each job; Ctrl-C, which the job's run caught (its outcome
        ``interrupted``), raises ``KeyboardInterrupt`` instead of its row."""
        for job in jobs:
            try:
                row = execute(job)
            except Exception as error:
                row = failed_row(job, error)
            if row.get("outcome") == "interrupted":
                raise KeyboardInterrupt
            yield row


class DaskEngine:
    """Runs the jobs as tasks of a ``dask.distributed`` client.

    Every worker connected forgets the worlds and missions it kept from earlier sweeps
    (their files may have changed since) and loads ``loads``; a worker that joins later
    loads them with its first jobs.

    Args:
        client: A connected ``distributed.Client``.
        description: Where the jobs run, for the user.
        loads: ``(mission path, world path)`` pairs to load on each worker.
    """

    def __init__(self, client, description: str, loads=()):
        started = time.perf_counter()
        self.client = client
        self.description = description
        client.run(reload_process_cache, tuple(loads))
        self.startup = time.perf_counter() - started

    def run(self, execute: Callable, jobs) -> Iterator[dict]:
        from dask.distributed import as_completed

        jobs = list(jobs)
        futures = self.client.map(execute, jobs, pure=False)
        by_future = dict(zip(futures, jobs))
        try:
            for future in as_completed(futures):
                yield _row(future, by_future[future])
                future.release()
        finally:
            self.client.cancel([f for f in futures if not f.done()])


def _row(future, job) -> dict:
    """The job's row; a task that failed outside the job (a worker died) is an error."""
    try:
        return future.result()
    except Exception as error:
        return failed_row(job, error)


@contextmanager
def open_engine(workers: int | None = None, scheduler: str | None = None,
                serial: bool = False, loads=()):
    """The engine to run a campaign on, its workers started; stopped on exit.

    Args:
        workers: Worker processes of this machine (one job at a time each); default:
            the number of CPUs.
        scheduler: Address of a running Dask scheduler (``tcp://HOST:PORT``) whose
            workers run the jobs instead.
        serial: Run in this process, without worker processes.
        loads: ``(mission path, world path)`` pairs every worker loads before the
            first job (:attr:`~.jobs.Campaign.loads`).

    Raises:
        OSError: the scheduler cannot be reached.
        WorkerStartError: the worker processes of this machine did not start.
    """
    if serial:
        yield SerialEngine(loads)
        return
    if scheduler:
        from dask.distributed import Client

        with Client(scheduler, timeout=CONNECT_TIMEOUT) as client:
            yield DaskEngine(client, f"Dask scheduler {scheduler}", loads)
        return
    from .pool import PoolEngine

    engine = PoolEngine(workers or os.cpu_count() or 1, loads)
    try:
        yield engine
    finally:
        engine.close()


def sweep(campaign, engine, execute: Callable = run_job,
          on_row: Callable | None = None) -> tuple:
    """Run every job of ``campaign`` on ``engine``.

    Args:
        campaign: A :class:`~.jobs.Campaign`.
        engine: From :func:`open_engine`.
        execute: ``execute(job) -> row``, importable where the jobs run.
        on_row: Called with each row as it arrives (progress).

    Returns:
        ``(rows, interrupted)``: the rows in the order they came, and whether Ctrl-C
        stopped the sweep before every job had finished.
    """
    rows = []
    try:
        for row in engine.run(execute, campaign.jobs):
            rows.append(row)
            if on_row is not None:
                on_row(row)
    except KeyboardInterrupt:
        return rows, True
    return rows, False
