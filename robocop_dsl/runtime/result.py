"""What a run returns: its outcome, transitions and cycle statistics."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..safety.report import SafetyReport


@dataclass(frozen=True)
class TransitionRecord:
    """A transition taken at ``time`` [s] because ``condition`` held; ``source`` and
    ``target`` are state paths (``pick/above``)."""

    time: float
    source: str
    target: str
    condition: str


@dataclass
class RunResult:
    """``outcome``: ``success`` or ``failure`` (the final state's), ``stopped`` (the
    duration cap came first), ``fault`` (a run-time fault with no handler) or
    ``interrupted`` (Ctrl-C). ``final_state`` is the active configuration at the end
    (leaf state paths joined by `` | ``). Times in seconds: ``mission_time`` includes
    the cycles that brought the robot to rest; ``cycle_times`` are whole cycles,
    observers included, and ``compute_times`` the controller's work in them (forward
    kinematics and QP), every cycle up to 65,536 of them, a uniform sample of the
    cycles beyond (the slowest always kept)."""

    outcome: str
    final_state: str
    mission_time: float
    cycles: int
    transitions: list = field(default_factory=list)
    cycle_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    compute_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    qp_failures: int = 0
    overruns: int = 0
    message: str = ""
    safety: SafetyReport = field(default_factory=SafetyReport)
    """Smallest clearances, largest excesses over limits, relaxed cycles."""
