"""A mission turned into what the runner executes: per state, lists of actions and
clauses as closures over the runner, built once before the first cycle."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable


@dataclass
class Clause:
    """``when CONDITION -> TARGET``: ``test(runner)`` is evaluated every cycle."""

    test: Callable
    target: str
    text: str
    uses_failure: bool = False


@dataclass
class StateProgram:
    """One state: its action lists and its own clauses, in source order."""

    name: str
    final: bool = False
    outcome: str = "success"
    enter: list = field(default_factory=list)
    during: list = field(default_factory=list)
    exit: list = field(default_factory=list)
    clauses: list = field(default_factory=list)


@dataclass
class Program:
    """The executable mission: states by name, top-level guards, the start state."""

    states: dict
    guards: list
    start: str

    def handles_failure(self, state: str) -> bool:
        """Whether a clause of ``state`` or a guard tests ``controller.failed``."""
        return any(c.uses_failure for c in self.states[state].clauses + self.guards)
