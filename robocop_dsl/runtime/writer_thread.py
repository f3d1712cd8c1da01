"""A thread that writes what the control loop hands it, in order, without holding the
loop up. The batches wait in a bounded backlog; what happens when it is full is the
writer's policy:

- :data:`DROP` (a real-time run): batches are written while the loop sleeps between
  its cycles: each cycle the loop ends opens a window until shortly before the next one
  starts (:meth:`WriterThread.loop_sleeps`; none while the loop is late), and the work
  waits for an open window before each of its steps (:meth:`WriterThread.turn`), so
  that the loop never waits for the interpreter longer than a step. The thread is
  woken only then, never in the middle of a cycle (a thread woken on the loop's
  processor takes it from the loop): a batch handed over during a cycle waits for the
  loop's sleep (once the loop has said when it sleeps). A full backlog
  drops its oldest batch (the caller reports it), but for what the writer's ``keep``
  keeps of it (a run's events), which goes at the head of the next batch.
- :data:`BATCH` (a headless run): the loop never sleeps, and only one thread runs
  Python at a time, so a writer working beside it would take the interpreter from it
  over and over, each switch costing both. The writer waits until the backlog is full,
  then writes it all while the loop waits (no deadline is missed, the log stays whole).
- :data:`WAIT` (no loop to protect: a process that only writes): each batch is written
  at once, in the caller's thread (a thread of its own would only take turns with the
  caller for the interpreter).
"""

from __future__ import annotations

import threading
import time
from collections import deque

DROP, BATCH, WAIT = "drop", "batch", "wait"
MARGIN = 5e-4
"""How long [s] before the loop's next cycle a :data:`DROP` writer stops its steps."""


class WriterThread:
    """Runs ``work(batch)`` in a daemon thread (in the caller's, for :data:`WAIT`) for
    each batch :meth:`put` hands over.

    Args:
        name: The thread's name.
        work: Called in the thread with each batch, in order.
        backlog: Batches waiting at most.
        policy: :data:`DROP`, :data:`BATCH` or :data:`WAIT`.
        keep: For :data:`DROP`, what of a batch (a list) must never be dropped, as a
            list (empty: none of it); the rest of the batch is dropped.

    Attributes:
        failure: The exception ``work`` raised, if any (then the batches after it are
            skipped); :meth:`close` raises it.
    """

    def __init__(self, name: str, work, backlog: int, policy: str, keep=None):
        self._work = work
        self._keep = keep
        self._backlog = backlog
        self._policy = policy
        self._waiting: deque = deque()
        self._busy = False
        lock = threading.Lock()
        self._ready = threading.Condition(lock)
        self._window = threading.Condition(lock)
        self._closed = False
        self.failure: BaseException | None = None
        self._window_end = 0.0
        self._thread = None
        if policy != WAIT:
            self._thread = threading.Thread(target=self._run, name=name, daemon=True)
            self._thread.start()

    def put(self, batch):
        """Hand ``batch`` over; returns the batch dropped to make room (what ``keep``
        kept of it went on with the next batch), or ``None``."""
        if self._thread is None:
            self._write(batch)
            return None
        dropped = None
        with self._ready:
            self._waiting.append(batch)
            if self._policy == DROP and len(self._waiting) > self._backlog:
                dropped = self._waiting.popleft()
                kept = self._keep(dropped) if self._keep is not None else []
                if kept:
                    self._waiting[0] = kept + self._waiting[0]
            if self._policy != DROP or not self._window_end:
                self._ready.notify_all()    # else when the loop sleeps (loop_sleeps)
            if self._policy == BATCH and len(self._waiting) >= self._backlog:
                self._ready.wait_for(lambda: not self._waiting and not self._busy)
        return dropped

    def loop_sleeps(self, until: float | None) -> None:
        """Called by the loop at the end of a cycle: it sleeps until ``until``
        [s, ``time.perf_counter()``] (``None``: it does not sleep)."""
        if self._policy == DROP and until is not None:
            with self._window:      # wakes the thread only when it has work
                self._window_end = until - MARGIN
                self._window.notify_all()
                if self._waiting and not self._busy:
                    self._ready.notify_all()

    def turn(self) -> None:
        """Called by ``work`` before each of its steps: a :data:`DROP` writer waits until
        the loop sleeps (at once once the run ended)."""
        if self._policy == DROP:
            with self._window:
                self._window.wait_for(
                    lambda: self._closed or time.perf_counter() < self._window_end)

    def close(self) -> None:
        """Wait for every batch handed over to be written; raise what ``work`` raised."""
        with self._ready:
            self._closed = True
            self._ready.notify_all()
            self._window.notify_all()
        if self._thread is not None:
            self._thread.join()
        if self.failure is not None:
            raise self.failure

    def _write(self, batch) -> None:
        if self.failure is None:
            try:
                self._work(batch)
            except Exception as error:  # reported by close(), in the caller's thread
                self.failure = error

    def _run(self) -> None:
        draining = False

        def due() -> bool:
            return self._closed or len(self._waiting) >= (
                self._backlog if self._policy == BATCH and not draining else 1)

        while True:
            with self._ready:
                self._ready.wait_for(due)
                if not self._waiting:
                    return
                batch = self._waiting.popleft()
                self._busy = draining = True
            self._write(batch)
            with self._ready:
                self._busy = False
                draining = bool(self._waiting)
                self._ready.notify_all()
