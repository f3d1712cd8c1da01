"""The run log (``events.jsonl``, the time series, ``run.mcap``) written by a process
of its own, as ``run --log`` does: only one thread of a process runs Python at a time,
so writers in the loop's process take turns with it; in their own process they work on
the other core.

The loop's side (:class:`LogProcess`, a run observer) packs the cycles into arrays,
their task views left to the writing process (:mod:`~robocop_dsl.runtime.record_batch`),
and sends them and the events down a pipe: in a real-time run, every :data:`PERIOD`
of mission time, from a thread that works while the loop sleeps and drops the oldest
cycles rather than make the loop wait (:mod:`~robocop_dsl.runtime.writer_thread`); in
a headless run, every :data:`BACKLOG`, in the loop's own thread (the loop never
sleeps: a thread beside it would only take turns with it). The writing process (:func:`main`,
in a session of its own; in a real-time run, at the idle priority: see
:func:`_yield_to_the_loop`) runs a :class:`~robocop_dsl.runtime.RunLogger` and the
``run.mcap`` writer on them. Neither SIGINT nor SIGTERM stops it, from its start: the
run's process stops the run and then the log. If that
process dies, the log stays as a killed run leaves it (the row groups and the MCAP
chunks written so far).
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import pickle
import signal
import struct
import subprocess
import sys
import threading
import traceback
from pathlib import Path

from ..diagnostics import RobocopError
from ..runtime.log import events_of, report_dropped
from ..runtime.record_batch import pack, unpack
from ..runtime.records import CycleRecord, Event, Observer
from ..runtime.run_info import RunInfo
from ..runtime.writer_thread import BATCH, DROP, WAIT, WriterThread

PERIOD = 0.1
"""Mission time [s] between two hand-overs to the writing process."""
BACKLOG = 1.0
"""Mission time [s] of cycles waiting to be sent at most (what the writing process has
left to write when the run stops, in a headless run)."""
NICENESS = 19
"""How much lower the writing process's scheduling priority is than the run's, from
the first cycle of a real-time run on, where Linux's idle scheduling class (the
process runs only on a processor nothing else wants, and yields it at once) is not
available."""
PIPE_SIZE = 1 << 20
"""Bytes the pipe to the writing process holds (Linux), about 5 s of cycles of the
pickup."""
_LENGTH = struct.Struct("<Q")
_STOPS = {signal.SIGINT, signal.SIGTERM}
_LAUNCH = ("import signal\n"
           "signal.signal(signal.SIGINT, signal.SIG_IGN)\n"
           "signal.signal(signal.SIGTERM, signal.SIG_IGN)\n"
           "signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT, signal.SIGTERM})\n"
           f"from {__name__} import main\n"
           "main()\n")
"""The writing process: started with SIGINT and SIGTERM blocked, it ignores them before
it lets them in, in a session of its own (a terminal's Ctrl-C goes to the run's
process group, not to it): the run's process stops the run, then the log."""


class LogProcessError(RobocopError):
    """The writing process failed: it did not start, or a writer raised."""


class LogProcess(Observer):
    """Writes the run's log in ``folder`` from a process of its own, started at once so
    that its imports overlap what the caller still does before the run; :meth:`prepare`
    tells it about the run and waits until it is ready.

    Args:
        folder: The log folder.

    Attributes:
        dropped: How many cycles were dropped.

    Raises:
        OSError: the folder cannot be made.
    """

    def __init__(self, folder):
        self._made = not Path(folder).exists()
        Path(folder).mkdir(parents=True, exist_ok=True)
        self.folder = str(folder)
        self.dropped = 0
        held = signal.pthread_sigmask(signal.SIG_BLOCK, _STOPS)
        try:            # the process starts with them held, ours come once it is started
            self._process = subprocess.Popen([sys.executable, "-c", _LAUNCH],
                                             stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                             start_new_session=True)
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, held)
        if hasattr(fcntl, "F_SETPIPE_SZ"):     # Linux: a pipe of seconds of cycles
            with contextlib.suppress(OSError):
                fcntl.fcntl(self._process.stdin.fileno(), fcntl.F_SETPIPE_SZ, PIPE_SIZE)
        self._policy: str | None = None
        self._runner = None
        self._items: list = []
        self._period = PERIOD
        self._next = PERIOD
        self._sender: WriterThread | None = None
        self._report = None
        self._ended = False

    def prepare(self, runner, policy: str) -> None:
        """Send the run's :class:`~robocop_dsl.runtime.run_info.RunInfo` and copies of its
        tasks (:meth:`~robocop_dsl.control.Task.detached`: the writing process computes the
        task views); wait until the process is ready to write (before the run).

        Args:
            runner: The run (or a :class:`~robocop_dsl.runtime.run_info.RunInfo` alone,
                for a run whose tasks are not logged).
            policy: ``drop``: a real-time run, whose sending thread drops the oldest
                cycles when :data:`BACKLOG` waits; ``batch``: a headless run, whose loop
                sends its cycles itself, every :data:`BACKLOG`.

        Raises:
            LogProcessError: the process could not start writing.
        """
        info = RunInfo.of(runner)
        tasks = () if isinstance(runner, RunInfo) else runner.tasks()
        self._report, self._policy = info.report, policy
        try:
            _send(self._process.stdin, ("start", self.folder, info.portable(), policy,
                                        {task.name: task.detached() for task in tasks}))
            reply = _receive(self._process.stdout)
        except OSError:                 # it died before reading: its error is on stderr
            reply = None
        except (pickle.PicklingError, TypeError, AttributeError) as error:
            self.close()
            raise LogProcessError(f"the run's tasks cannot be sent to the log's writing "
                                  f"process: {error}") from None
        if reply is None or reply[0] != "ready":
            self._process.wait()
            raise LogProcessError("the log's writing process did not start" +
                                  (f": {reply[1]}" if reply else ""))

    def on_start(self, runner) -> None:
        if self._policy is None:
            self.prepare(runner, BATCH)
        self._runner = runner
        if self._policy == BATCH:     # the loop sends its cycles itself: one batch a second
            self._period = self._next = BACKLOG
        self._sender = WriterThread("run log sender", self._send,
                                    max(1, round(BACKLOG / self._period)),
                                    WAIT if self._policy == BATCH else self._policy,
                                    keep=events_of)

    def close(self) -> None:
        """End the process if the run did not (a run that never started), and remove
        the folder it made when nothing was written in it."""
        if not self._ended and self._process.poll() is None:
            self._process.kill()
            self._process.wait()
        if self._made and self._policy is None:
            with contextlib.suppress(OSError):      # not empty: someone else's files
                os.rmdir(self.folder)

    def on_cycle(self, record: CycleRecord) -> None:
        self._items.append(record)
        if record.time >= self._next - 1e-9:
            self._next = record.time + self._period
            self._hand_over()
        if self._sender is not None:
            self._sender.loop_sleeps(getattr(self._runner, "next_cycle_at", None))

    def on_event(self, event: Event) -> None:
        self._items.append(event)

    def on_stop(self, result) -> None:
        """Send the last cycles and wait until the process has finished the log (its
        exit is reaped in a thread: the files are complete once it replied)."""
        if self._sender is None:
            self.close()
            return
        self._hand_over()
        try:
            self._sender.close()
            _send(self._process.stdin, ("stop",))
            reply = _receive(self._process.stdout)
            problems = reply[1] if reply else ["the log's writing process is gone"]
        except Exception as error:  # a broken pipe, cycles that could not be packed
            problems = [f"the log could not be sent to its writing process: {error}"]
        finally:
            self._sender = None
            with contextlib.suppress(OSError):
                self._process.stdin.close()
            self._ended = True          # it ends on its own, at the latest at end of input
            threading.Thread(target=self._process.wait, name="run log reaper",
                             daemon=True).start()
        if problems:
            raise LogProcessError("; ".join(problems))

    def _hand_over(self) -> None:
        items, self._items = self._items, []
        if not items or self._sender is None:
            return
        self.dropped += report_dropped(self._report, "time series and run.mcap",
                                       self._sender.put(items))

    def _send(self, items: list) -> None:
        """In the sending thread: the items as messages, cycles packed."""
        messages, records = [], []
        for item in items + [None]:
            if isinstance(item, CycleRecord):
                records.append(item)
                continue
            if records:
                self._sender.turn()
                messages.append(("cycles", pack(records)))
                records = []
            if item is not None:
                messages.append(("event", item))
        for message in messages:
            self._sender.turn()
            _send(self._process.stdin, message)


def _send(stream, message) -> None:
    data = pickle.dumps(message, protocol=pickle.HIGHEST_PROTOCOL)
    stream.write(_LENGTH.pack(len(data)) + data)
    stream.flush()


def _receive(stream):
    """The next message, or ``None`` at the end of the stream."""
    header = stream.read(_LENGTH.size)
    if len(header) < _LENGTH.size:
        return None
    return pickle.loads(stream.read(_LENGTH.unpack(header)[0]))


def main() -> None:
    """The writing process: the writers of the log in the folder the run names, fed
    the cycles and events the run sends, until it says stop (or disappears)."""
    requests = sys.stdin.buffer
    replies = os.fdopen(os.dup(sys.stdout.fileno()), "wb")
    os.dup2(sys.stderr.fileno(), sys.stdout.fileno())       # stray prints: to stderr
    from ..runtime.log import RunLogger, warm_up
    from ..world import load_world
    from . import mcap_log

    warm_up()
    start = _receive(requests)
    if start is None:
        os._exit(0)
    _, folder, info, policy, tasks = start
    try:
        writers = [RunLogger(folder, info.joint_names, WAIT),
                   mcap_log(load_world(info.world_path), info.joint_names, folder, WAIT)]
        for writer in writers:
            writer.on_start(info)
    except Exception as error:  # sent to the run's process, which reports it
        _send(replies, ("error", _text(error)))
        os._exit(1)
    _send(replies, ("ready",))
    if policy == DROP:
        _yield_to_the_loop()
    problems: list = []
    while (message := _receive(requests)) is not None:
        if message[0] == "stop":
            for writer in writers:
                try:
                    writer.on_stop(None)
                except Exception as error:  # every writer gets its on_stop
                    problems.append(_text(error))
            _send(replies, ("done", problems))
            replies.close()
            os._exit(0)
        if problems:
            continue
        try:
            for item in unpack(message[1], tasks) if message[0] == "cycles" else [message[1]]:
                for writer in writers:
                    (writer.on_cycle if message[0] == "cycles" else writer.on_event)(item)
        except Exception as error:  # told at the stop; what comes after is not written
            problems.append(_text(error))
    os._exit(0)                   # the run's process is gone: leave the log as it is


def _yield_to_the_loop() -> None:
    """In a real-time run, from the first cycle on, every thread of the writing process
    (its writers' too) runs only when a processor has nothing else to do: on a busy
    machine the loop never waits for it. Linux sets priorities per thread."""
    threads = [int(task) for task in os.listdir("/proc/self/task")] \
        if os.path.isdir("/proc/self/task") else [0]
    for thread in threads:
        try:
            os.sched_setscheduler(thread, os.SCHED_IDLE, os.sched_param(0))
        except (AttributeError, OSError):
            with contextlib.suppress(OSError):
                os.setpriority(os.PRIO_PROCESS, thread, NICENESS)


def _text(error: BaseException) -> str:
    return "".join(traceback.format_exception_only(type(error), error)).strip()

