"""Where jobs run: in this process, on a local Dask cluster of processes, or on a
running Dask scheduler. Every engine yields one row per job as jobs finish; the order
of the rows does not matter (the table is sorted by job). A local cluster's scheduler,
workers and dashboard listen on the loopback interface only."""

from __future__ import annotations

import logging
import os
from contextlib import contextmanager
from typing import Callable, Iterator

from .worker import job_row, run_job

CONNECT_TIMEOUT = "20s"
LOOPBACK = "127.0.0.1"


class SerialEngine:
    """Runs the jobs one after the other in this process."""

    description = "serial, in this process"

    def run(self, execute: Callable, jobs) -> Iterator[dict]:
        for job in jobs:
            try:
                row = execute(job)
            except Exception as error:
                row = failed_row(job, error)
            yield row


class DaskEngine:
    """Runs the jobs as tasks of a ``dask.distributed`` client.

    Args:
        client: A connected ``distributed.Client``.
        description: Where the jobs run, for the user.
    """

    def __init__(self, client, description: str):
        self.client = client
        self.description = description

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


def failed_row(job, error: Exception) -> dict:
    """The row of a job whose ``execute`` raised instead of returning a row."""
    return {**job_row(job), "outcome": "error", "message": f"{type(error).__name__}: {error}"}


@contextmanager
def open_engine(workers: int | None = None, scheduler: str | None = None,
                serial: bool = False):
    """The engine to run a campaign on, closed (with its local cluster) on exit.

    Args:
        workers: Worker processes of a local cluster (one thread each); default: the
            number of CPUs.
        scheduler: Address of a running Dask scheduler (``tcp://HOST:PORT``) to use
            instead of a local cluster.
        serial: Run in this process, without Dask.
    """
    if serial:
        yield SerialEngine()
        return
    from dask.distributed import Client, LocalCluster

    if scheduler:
        with Client(scheduler, timeout=CONNECT_TIMEOUT) as client:
            yield DaskEngine(client, f"Dask scheduler {scheduler}")
        return
    count = workers or os.cpu_count() or 1
    with LocalCluster(n_workers=count, threads_per_worker=1, processes=True,
                      host=LOOPBACK, dashboard_address=f"{LOOPBACK}:0",
                      silence_logs=logging.ERROR) as cluster, \
            Client(cluster) as client:
        yield DaskEngine(client, f"local Dask cluster of {count} worker processes")


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
