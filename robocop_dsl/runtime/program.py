"""A mission turned into what the runner executes: its machines, and per state lists
of actions and clauses as closures, built once before the first cycle.

An action is ``action(runner)``; a clause's test is ``test(runner, owner)``, where
``owner`` is the :class:`~robocop_dsl.runtime.statechart.Activation` of the state that
owns the clause (for a machine's top-level clause, that machine's active state).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Callable


@dataclass
class Clause:
    """``when CONDITION -> TARGET { ACTIONS }``: ``test(runner, owner)`` is evaluated
    every cycle the clause is checked; ``target`` is a state of the clause's machine, by
    its local name; ``actions`` run between the exits and the enters."""

    test: Callable
    target: str
    text: str
    uses_failure: bool = False
    actions: list = field(default_factory=list)


@dataclass
class StateProgram:
    """One state: its action lists, its own clauses in source order and its machines
    (one for a compound state, one per region, in declaration order, for a parallel
    state). ``path`` names it from the mission's machine, ``machine`` is the path of
    the machine it belongs to."""

    name: str
    final: bool = False
    outcome: str = "success"
    enter: list = field(default_factory=list)
    during: list = field(default_factory=list)
    exit: list = field(default_factory=list)
    clauses: list = field(default_factory=list)
    path: str = ""
    machine: str = ""
    machines: list = field(default_factory=list)
    parallel: bool = False


@dataclass
class MachineProgram:
    """A machine: its states by local name in declaration order, the local name of its
    start state and its top-level guards. ``path`` is ``""`` for the mission's machine,
    the state's path for a compound state's, ``STATE/REGION`` for a region's."""

    path: str
    states: dict
    start: str
    guards: list = field(default_factory=list)
    region: str | None = None

    def walk(self):
        """Every machine from this one down, parents first, in declaration order."""
        yield self
        for state in self.states.values():
            for machine in state.machines:
                yield from machine.walk()


class Program:
    """The executable mission: the mission's machine and, by path, every state and
    every machine nested in it; its vars' specs
    (:class:`~robocop_dsl.compile.variables.VarSpec`)."""

    def __init__(self, machine: MachineProgram, variables: tuple = ()):
        self.machine = machine
        self.variables = tuple(variables)
        self.machines = {m.path: m for m in machine.walk()}
        self.states = {state.path: state for m in self.machines.values()
                       for state in m.states.values()}

    def __repr__(self) -> str:
        return f"Program({len(self.machines)} machines, {len(self.states)} states)"

    @property
    def start(self) -> str:
        """The path of the mission's start state."""
        return self.machine.states[self.machine.start].path

    @property
    def guards(self) -> list:
        """The mission's top-level clauses."""
        return self.machine.guards

    def handles_failure(self, active: Iterable[str]) -> bool:
        """Whether a clause checked in the configuration of the ``active`` state paths
        tests ``controller.failed``: the own clauses of its non-final states and the
        guards of the machines they belong to."""
        for path in active:
            state = self.states[path]
            if not state.final and any(
                    c.uses_failure for c in state.clauses + self.machines[state.machine].guards):
                return True
        return False
