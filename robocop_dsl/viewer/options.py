"""The viewer processor's options, read from the world's ``processors:`` section."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import ViewerError

PROCESSOR_TYPE = "meshcat"
DEFAULT_PERIOD = 0.04


@dataclass(frozen=True)
class ViewerOptions:
    """How often the viewer publishes.

    Attributes:
        period: Time between two published frames [s]; a replay has one animation
            frame per period of run time.
    """

    period: float = DEFAULT_PERIOD

    def __post_init__(self):
        if not isinstance(self.period, (int, float)) or not math.isfinite(self.period) \
                or self.period <= 0:
            raise ViewerError(f"viewer period must be a positive duration, got {self.period!r}")


def viewer_options(world) -> ViewerOptions:
    """The options of the world's ``type: meshcat`` processor (defaults without one).

    Args:
        world: A :class:`robocop_dsl.world.World`; durations in its processor options
            are already in seconds.

    Raises:
        ViewerError: the world declares more than one viewer, or a bad period.
    """
    viewers = [p for p in world.processors.values() if p.type == PROCESSOR_TYPE]
    if len(viewers) > 1:
        names = ", ".join(p.name for p in viewers)
        raise ViewerError(f"the world declares several {PROCESSOR_TYPE} processors ({names})")
    if not viewers:
        return ViewerOptions()
    return ViewerOptions(period=viewers[0].options.get("period", DEFAULT_PERIOD))
