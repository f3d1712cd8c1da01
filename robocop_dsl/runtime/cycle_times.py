"""Cycle and compute times of a run in constant memory."""

from __future__ import annotations

import math
import random

import numpy as np

SAMPLED_CYCLES = 1 << 16
"""How many cycle times a run keeps for its statistics (a uniform sample beyond)."""


class CycleTimes:
    """Cycle and compute times [s] of a run in constant memory: every cycle until
    ``capacity``, then a uniform sample of them (reservoir sampling, seeded), the slowest
    cycle always among them."""

    def __init__(self, capacity: int = SAMPLED_CYCLES):
        self._cycle = np.empty(capacity)
        self._compute = np.empty(capacity)
        self._count = 0
        self._slowest = (-math.inf, 0.0)
        self._random = random.Random(0)

    def __len__(self) -> int:
        return self._count

    def add(self, cycle_time: float, compute_time: float) -> None:
        count, capacity = self._count, len(self._cycle)
        self._count += 1
        if cycle_time > self._slowest[0]:
            self._slowest = (cycle_time, compute_time)
        slot = count if count < capacity else self._random.randrange(count + 1)
        if slot < capacity:
            self._cycle[slot], self._compute[slot] = cycle_time, compute_time

    def arrays(self) -> tuple:
        """``(cycle_times, compute_times)`` of the kept cycles, the slowest included."""
        kept = min(self._count, len(self._cycle))
        cycles, computes = self._cycle[:kept].copy(), self._compute[:kept].copy()
        if kept and self._slowest[0] > cycles.max():
            cycles[0], computes[0] = self._slowest
        return cycles, computes
