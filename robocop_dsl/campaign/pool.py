"""Running a campaign on worker processes of this machine, started once per sweep.

The workers are forked from a fork server (``multiprocessing``'s ``forkserver``) that
imported the package once, in a fresh interpreter. Each loads every mission of the
campaign on each of its world variants into its :data:`~.worker.PROCESS_CACHE`, then
runs jobs one after the other until the sweep ends. A job then costs its worker the
job alone: the job and its row cross a pipe, a few hundred bytes each way. Nothing
listens on the network (the fork server's socket is a file in a private folder).

Workers ignore Ctrl-C: the sweeping process stops them (SIGTERM) when Ctrl-C or SIGTERM
ends the sweep. A worker that dies (a crash in a native library, the kernel killing
it) takes the pool down with it: the pool is started again and the unfinished jobs are
sent again; a job that was running when its worker died :data:`ATTEMPTS` times is
recorded as an ``error``.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import threading
import time
from collections import Counter
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from multiprocessing import forkserver

from .worker import PROCESS_CACHE, failed_row

PRELOAD = ["robocop_dsl.campaign.pool", "robocop_dsl.runtime.mission"]
"""Modules the fork server imports once; every worker forked from it has them."""
STARTUP_TIMEOUT = 300.0
"""Wall time [s] the workers get to import the package and load the missions."""
ATTEMPTS = 2
"""How many times a job may be running when its worker dies before it is an error."""
IDLE = -1
"""A worker's slot when it runs no job."""

_slot = None
"""In a worker: ``(running, index)``, the shared array of running jobs and its place."""


class WorkerStartError(RuntimeError):
    """The worker processes could not start (the package does not import in them)."""


class WorkerDied(RuntimeError):
    """The worker process running a job died, every time the job was sent."""


class PoolEngine:
    """Runs the jobs on ``workers`` processes of this machine, one job at a time each.

    Args:
        workers: How many worker processes.
        loads: ``(mission path, world path)`` pairs each worker loads as it starts.

    Attributes:
        startup: Wall time [s] until every worker had started and loaded ``loads``.

    Raises:
        WorkerStartError: a worker died while starting, or they were not all ready
            within :data:`STARTUP_TIMEOUT`.
    """

    def __init__(self, workers: int, loads=()):
        self.workers = workers
        self.description = f"{workers} worker processes on this machine"
        self._loads = tuple(loads)
        self._context = multiprocessing.get_context("forkserver")
        self._context.set_forkserver_preload(PRELOAD)
        self._pool = None
        self._futures: dict = {}
        started = time.perf_counter()
        self._start()
        self.startup = time.perf_counter() - started

    def _start(self) -> None:
        """Start the workers and wait until each has loaded the campaign's missions."""
        self._running = self._context.Array("q", [IDLE] * self.workers)
        self._pids = self._context.Array("q", [0] * self.workers, lock=False)
        self._ready = self._context.Value("i", 0)
        self._pool = ProcessPoolExecutor(
            self.workers, mp_context=self._context, initializer=_start_worker,
            initargs=(self._loads, self._running, self._pids, self._ready))
        with _ctrl_c_ignored():  # the fork server and the workers it forks inherit it
            forkserver.ensure_running()
        deadline = time.monotonic() + STARTUP_TIMEOUT
        try:
            with _signals_held(signal.SIGINT, signal.SIGTERM):  # no worker half forked
                pings = [self._pool.submit(os.getpid) for _ in range(self.workers)]
            while self._ready.value < self.workers:
                failed = next((f.exception() for f in pings if f.done() and f.exception()),
                              None)
                if failed is not None or time.monotonic() > deadline:
                    raise WorkerStartError(f"the worker processes did not start: "
                                           f"{failed or f'not ready in {STARTUP_TIMEOUT:g} s'}")
                time.sleep(0.01)
        except BaseException:
            self.close()
            raise

    def run(self, execute, jobs):
        """Yield the row of each job as it finishes, in any order."""
        todo = {job.index: job for job in jobs}
        attempts: Counter = Counter()
        while todo:
            if self._pool is None:
                try:
                    self._start()
                except WorkerStartError as error:
                    yield from (failed_row(job, error) for job in todo.values())
                    return
            self._futures = {self._pool.submit(_execute, execute, job): job
                             for job in todo.values()}
            for future in as_completed(self._futures):
                job, error = self._futures[future], future.exception()
                if isinstance(error, BrokenProcessPool):
                    break
                del todo[job.index]
                yield failed_row(job, error) if error is not None else future.result()
            else:
                return
            lost = self._restart() & todo.keys()
            for index in sorted(lost or todo.keys()):
                attempts[index] += 1
                if attempts[index] >= ATTEMPTS:
                    yield failed_row(todo.pop(index), WorkerDied(
                        f"its worker process died while running it, {ATTEMPTS} times"))

    def _restart(self) -> set:
        """Close the broken pool; the jobs that were running in the workers that died
        (the others were stopped with SIGTERM and cleared their slots)."""
        self._futures = {}
        self.close()
        return {index for index in self._running if index != IDLE}

    @property
    def pids(self) -> list:
        """The process ids of the workers."""
        return [pid for pid in self._pids if pid]

    def close(self) -> None:
        """Stop the workers: at once (SIGTERM) when starting or with jobs unfinished,
        else as they become idle."""
        pool, self._pool = self._pool, None
        if pool is None:
            return
        for future in self._futures:
            future.cancel()
        if self._ready.value < self.workers or any(not f.done() for f in self._futures):
            for pid in self.pids:
                _terminate(pid)
        pool.shutdown(wait=True, cancel_futures=True)


@contextmanager
def _ctrl_c_ignored():
    """Ignore SIGINT and hold SIGTERM meanwhile (from the main thread only; processes
    started inherit the first). The fork server is started so: Ctrl-C reaches the
    sweeping process alone, and no signal leaves the fork server half started."""
    with _signals_held(signal.SIGTERM), _handled(signal.SIG_IGN, signal.SIGINT):
        yield


@contextmanager
def _signals_held(*numbers):
    """Hold the signals ``numbers`` meanwhile (from the main thread only) and raise
    them after, to their own handlers."""
    caught = []
    with _handled(lambda number, frame: caught.append(number), *numbers):
        yield
    for number in dict.fromkeys(caught):
        signal.raise_signal(number)


@contextmanager
def _handled(handler, *numbers):
    """``handler`` for the signals ``numbers`` meanwhile, when called from the main
    thread."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {number: signal.signal(number, handler) for number in numbers}
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, signal.SIG_DFL if handler is None else handler)


def _terminate(pid: int) -> None:
    """SIGTERM to the worker process ``pid``."""
    try:
        os.kill(pid, signal.SIGTERM)
    except ProcessLookupError:
        return


def _start_worker(loads, running, pids, ready) -> None:
    """In a new worker: ignore Ctrl-C, take a slot, load ``loads``."""
    global _slot
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    with ready.get_lock():
        index = sum(1 for pid in pids if pid)
        pids[index] = os.getpid()
    _slot = (running, index)
    signal.signal(signal.SIGTERM, _stopped)
    PROCESS_CACHE.preload(loads)
    with ready.get_lock():
        ready.value += 1


def _stopped(signum, frame) -> None:
    """SIGTERM in a worker: it was stopped, its job did not kill it; clear the slot."""
    running, index = _slot
    running[index] = IDLE
    os._exit(128 + signum)


def _execute(execute, job) -> dict:
    """``execute(job)`` in a worker, its slot saying which job runs meanwhile."""
    running, index = _slot
    running[index] = job.index
    try:
        return execute(job)
    finally:
        running[index] = IDLE
