"""``run --event NAME@TIME``: reading the option and checking its names against the
mission (the observer that raises the events is in :mod:`.event_schedule`)."""

from __future__ import annotations

import argparse
import difflib
import re
from dataclasses import dataclass


_SCHEDULED = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)@([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)(ms|s)?$")


@dataclass(frozen=True)
class ScheduledEvent:
    """Raise ``name`` at mission time ``time`` [s]."""

    name: str
    time: float


def scheduled_event(text: str) -> ScheduledEvent:
    """``NAME@TIME`` (``go@2.5``, ``go@2.5s``, ``go@500ms``), for argparse."""
    match = _SCHEDULED.match(text.strip())
    if match is None:
        raise argparse.ArgumentTypeError(
            f"'{text}' is not NAME@TIME (write e.g. go@2.5 or go@500ms)")
    name, number, unit = match.groups()
    return ScheduledEvent(name, float(number) * (1e-3 if unit == "ms" else 1.0))


def unknown_events(scheduled, known) -> list:
    """One message per scheduled event the mission never reads or emits."""
    messages = []
    for event in scheduled:
        if event.name not in known:
            close = difflib.get_close_matches(event.name, sorted(known), n=1, cutoff=0.5)
            hint = f"; did you mean '{close[0]}'?" if close else ""
            listed = ", ".join(sorted(known)) or "none"
            messages.append(f"--event {event.name}@{event.time:g}: the mission has no event "
                            f"'{event.name}' (its events: {listed}){hint}")
    return messages

