"""The run's topics (:mod:`.topics`) written while the run goes: a run observer that
hands the cycles and events over to a writer thread, where they become messages for a
sink (the ``run.mcap`` file, the Foxglove server)."""

from __future__ import annotations

from ..runtime.log import event_json, events_of, report_dropped
from ..runtime.records import CycleRecord, Observer
from ..runtime.writer_thread import DROP, WriterThread
from .topics import RunTopics

MCAP_PERIOD = 1.0
"""Mission time [s] between two hand-overs to the ``run.mcap`` writer (and two
checkpoints of the file)."""
LIVE_PERIOD = 0.04
"""Mission time [s] between two hand-overs to the live server (and between two of its
``/tf`` messages)."""
MCAP_TF_PERIOD = 0.02
"""Mission time [s] between two ``/tf`` messages of ``run.mcap``: 50 per second."""
STEP = 10
"""Cycles made into messages at a time by a ``drop`` writer, between two turns given to
the loop (see :meth:`~robocop_dsl.runtime.writer_thread.WriterThread.turn`); the other
policies make a whole hand-over at once (the messages of many cycles cost little more
than those of one)."""
BACKLOG = 4.0
"""Mission time [s] of cycles waiting for a writer at most (see
:mod:`~robocop_dsl.runtime.writer_thread`)."""


class TopicStream(Observer):
    """Publishes a run to ``sink`` from a writer thread.

    Make it before the run (it copies the world's kinematic model). Its ``opening``
    messages (the URDF, the fixed bodies) go out when the run starts.

    Args:
        topics: The run's :class:`~.topics.RunTopics`.
        sink: Has ``write(messages)``, ``checkpoint()`` (after each hand-over) and
            ``close()``; a :class:`~.mcap_file.McapFile` or a
            :class:`~.foxglove_live.FoxgloveServer`.
        name: The writer's name in a ``dropped`` event (``run.mcap``, ``foxglove``).
        period: Mission time [s] between two hand-overs.
        policy: What the writer does when :data:`BACKLOG` of cycles wait
            (:mod:`~robocop_dsl.runtime.writer_thread`): ``drop`` the oldest (live, or a
            real-time run), ``batch`` (a headless run) or ``wait``.

    Attributes:
        dropped: How many cycles the writer dropped.
    """

    def __init__(self, topics: RunTopics, sink, name: str, period: float, policy: str):
        self.topics = topics
        self.sink = sink
        self.name = name
        self.period = period
        self._policy = policy
        self._items: list = []
        self._next = period
        self._writer: WriterThread | None = None
        self._runner = None
        self._report = None
        self.dropped = 0

    def on_start(self, runner) -> None:
        """Send the opening messages, start the writer. ``runner``: the run, or its
        :class:`~robocop_dsl.runtime.run_info.RunInfo`."""
        self._report = getattr(runner, "report", None)
        self._runner = runner
        self.sink.write(self.topics.opening())
        self.sink.checkpoint()
        backlog = max(2, round(BACKLOG / self.period))
        self._writer = WriterThread(f"{self.name} writer", self._write, backlog, self._policy,
                                    keep=events_of)

    def on_cycle(self, record: CycleRecord) -> None:
        self._items.append(record)
        if record.time >= self._next - 1e-9:
            self._next = record.time + self.period
            self._hand_over()
        if self._writer is not None:
            self._writer.loop_sleeps(getattr(self._runner, "next_cycle_at", None))

    def on_event(self, event) -> None:
        self._items.append(event_json(event))

    def on_stop(self, result) -> None:
        if self._writer is None:
            return
        self._hand_over()
        try:
            self._writer.close()
        finally:
            self._writer = None
            self.sink.close()

    def _hand_over(self) -> None:
        items, self._items = self._items, []
        if not items or self._writer is None:
            return
        self.dropped += report_dropped(self._report, self.name, self._writer.put(items))

    def _write(self, items: list) -> None:
        """In the writer thread: the messages of a hand-over, in time order, made
        :data:`STEP` cycles at a time by a ``drop`` writer, all at once by the others."""
        step = STEP if self._policy == DROP else len(items)
        messages: list = []
        records: list = []
        for item in items + [None]:
            if isinstance(item, CycleRecord):
                records.append(item)
                if len(records) < step:
                    continue
            if records:
                self._writer.turn()
                messages += self.topics.cycles(records)
                records = []
            if item is not None and not isinstance(item, CycleRecord):
                messages += self.topics.event(item)
        messages.sort(key=lambda message: message[1])
        self.sink.write(messages)
        self.sink.checkpoint()
