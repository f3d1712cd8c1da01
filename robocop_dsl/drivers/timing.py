"""Periods and rates: reading them from a processor's options, and keeping a thread
on its period."""

from __future__ import annotations

import re
import time

from .errors import DriverConfigError

_RATE = re.compile(r"^\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(Hz|kHz|MHz)\s*$")
_HERTZ = {"Hz": 1.0, "kHz": 1e3, "MHz": 1e6}
_DURATION = re.compile(r"^\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(us|ms|s)\s*$")
_SECONDS = {"us": 1e-6, "ms": 1e-3, "s": 1.0}


def parse_rate(value) -> float:
    """A rate as written in a world file (``1kHz``, ``500 Hz``, or a number of hertz).

    Returns:
        The rate [Hz].

    Raises:
        DriverConfigError: Not a positive rate.
    """
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        rate = float(value)
    else:
        match = _RATE.match(str(value))
        if match is None:
            raise DriverConfigError(f"rate '{value}' is not a rate (write e.g. 1kHz or 500Hz)")
        rate = float(match.group(1)) * _HERTZ[match.group(2)]
    if rate <= 0:
        raise DriverConfigError(f"rate '{value}' must be positive")
    return rate


def parse_duration(value, what: str) -> float:
    """A duration: seconds (the world loader already converts ``5ms``) or a string.

    Returns:
        The duration [s].

    Raises:
        DriverConfigError: Not a positive duration.
    """
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        seconds = float(value)
    else:
        match = _DURATION.match(str(value))
        if match is None:
            raise DriverConfigError(f"{what} '{value}' is not a duration (write e.g. 1ms)")
        seconds = float(match.group(1)) * _SECONDS[match.group(2)]
    if seconds <= 0:
        raise DriverConfigError(f"{what} '{value}' must be positive")
    return seconds


def period_from_options(options: dict, default: float) -> float:
    """The period [s] given by ``rate:`` or ``period:`` in ``options``, else ``default``.

    Raises:
        DriverConfigError: Both are given, or one is not valid.
    """
    if "rate" in options and "period" in options:
        raise DriverConfigError("give either 'rate' or 'period', not both")
    if "rate" in options:
        return 1.0 / parse_rate(options["rate"])
    if "period" in options:
        return parse_duration(options["period"], "period")
    return default


class Ticker:
    """Wakes a thread at ``start + k * period``; a late thread skips the ticks it missed
    instead of bursting to catch up.

    Args:
        period: The period [s].
        clock: Time source [s].
    """

    def __init__(self, period: float, clock=time.monotonic):
        self.period = period
        self._clock = clock
        self._next = clock() + period
        self.missed = 0

    def wait(self, stop=None) -> float:
        """Sleep until the next tick, or until ``stop`` (a ``threading.Event``) is set.

        Returns:
            The time of waking [s].
        """
        delay = self._next - self._clock()
        if delay > 0:
            if stop is not None:
                stop.wait(delay)
            else:
                time.sleep(delay)
        now = self._clock()
        late = int((now - self._next) // self.period)
        if late > 0:
            self.missed += late
        self._next += (max(late, 0) + 1) * self.period
        return now
