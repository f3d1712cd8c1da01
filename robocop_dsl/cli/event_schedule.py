"""``run --event NAME@TIME``: events raised at given mission times, as an operator would
raise them (``runner.emit``)."""

from __future__ import annotations

from ..runtime.records import Observer

TIME_TOLERANCE = 1e-9   # [s] a cycle at time t raises the events scheduled up to t + this


class EventSchedule(Observer):
    """Raises each scheduled event after the first cycle whose time reaches its time;
    ``event NAME`` clauses see it from the next cycle on."""

    wants_tasks = False

    def __init__(self, events):
        self.pending = sorted(events, key=lambda e: e.time)
        self.runner = None

    def on_start(self, runner) -> None:
        self.runner = runner

    def on_cycle(self, record) -> None:
        while self.pending and self.pending[0].time <= record.time + TIME_TOLERANCE:
            self.runner.emit(self.pending.pop(0).name)
