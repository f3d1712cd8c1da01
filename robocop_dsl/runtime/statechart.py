"""The run-time semantics of the mission's machines: nested machines, behaviour
instances (expanded by the compiler) and parallel regions (DESIGN "Semantics of one
cycle").

The model is a :class:`~robocop_dsl.runtime.program.Program`; a :class:`Statechart`
holds its active configuration and runs it, as SCXML and Sismic do, with a few named
functions: :meth:`Statechart.check` selects and fires the transitions of a machine,
:meth:`Statechart.exit` and :meth:`Statechart.enter` leave and enter states,
:meth:`Statechart.during` runs the ``during`` blocks. Each call of
:meth:`Statechart.start` and :meth:`Statechart.transitions` returns a
:class:`MacroStep` listing what happened, for observers and tests.

Semantic choices:

- Every active machine has one active state; a compound state's machine is active while
  the state is, and so is every region of an active parallel state.
- ``check(M)``: nothing when M's active state S is final. Else each machine of S is
  checked, regions in declaration order (each may take a transition in the same
  cycle); if one did, nothing else of M is checked. Else S's own clauses, then M's
  guards (owner S), in writing order; the first true one fires. So: innermost first, at
  most one transition per machine and cycle.
- Firing a clause of M from S to T (T may be S: a self-transition leaves and
  re-enters): the ``on_transition`` hook, exit S, the clause's actions, enter T.
- Exit: from the innermost active state outwards; a parallel state's regions are left in
  reverse declaration order (the last entered is the first left), then the parallel
  state itself.
- Enter: the state's ``enter`` block, then each of its machines in declaration order:
  that machine's ``visits`` counters reset, its start state entered the same way.
- ``during`` blocks run in pre-order: a state, then its regions' active states in
  declaration order (outermost first).
- Only a final state of the mission's machine ends a run (:attr:`MacroStep.outcome`); a
  nested machine in a final state stays there until a clause of its parent leaves it.
- A clause's *owner* is the state it belongs to, or for a machine's guard that
  machine's active state: ``elapsed`` is the time since the owner's entry.
- ``S.visits`` counts the entries of S since its machine was entered, this one
  included; ``S.FINAL`` holds while S's machine is in its final state FINAL,
  ``S.REGION.FINAL`` the same for one region, ``S.done`` while every region is final.
- Events are latched: ``event E`` holds in cycle k for an owner entered in cycle e when
  E was raised in a cycle r with e <= r < k.

Actions and clause tests get a *context* (the runner): an object with ``time`` [s]
and ``cycle``, read when a state is entered.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from itertools import chain

from ..compile.state_graph import join
from .program import MachineProgram, Program, StateProgram


class StepFailed(Exception):
    """An action or a condition raised; ``where`` names it in the mission's words (the
    block or clause, the state), the cause is chained."""

    def __init__(self, where: str):
        super().__init__(where)
        self.where = where


@dataclass(frozen=True)
class Activation:
    """One entry of the state at ``path``: mission ``time`` [s] and ``cycle`` it was
    entered at."""

    path: str
    time: float
    cycle: int


@dataclass(frozen=True)
class MicroStep:
    """One transition taken (``source`` ``None``: the start-up), with the states exited
    (innermost first) and entered (outermost first), as paths."""

    source: str | None
    target: str
    condition: str
    exited: tuple[str, ...] = ()
    entered: tuple[str, ...] = ()


@dataclass(frozen=True)
class MacroStep:
    """What the start-up or the transitions of one cycle did: the micro steps in the
    order taken, the configuration's text afterwards and, when a final state of the
    mission's machine was entered, its path and outcome."""

    cycle: int
    time: float
    steps: tuple[MicroStep, ...]
    configuration: str
    final: str | None = None
    outcome: str | None = None

    @property
    def exited(self) -> tuple[str, ...]:
        return tuple(path for step in self.steps for path in step.exited)

    @property
    def entered(self) -> tuple[str, ...]:
        return tuple(path for step in self.steps for path in step.entered)


class Statechart:
    """The active configuration of a :class:`Program` and the functions that run it.

    Args:
        program: The executable mission.
        on_transition: Called as ``on_transition(source, target, condition)`` (paths and
            the condition's text) when a clause fires, before any action runs.

    Attributes:
        running: The path of the state whose block or clause runs actions right now,
            else ``None``.
    """

    def __init__(self, program: Program, on_transition: Callable | None = None):
        self.program = program
        self.on_transition = on_transition
        self.running: str | None = None
        self._active: dict[str, Activation] = {}
        self._visits: dict[str, int] = {}
        self._latest: dict[str, int] = {}
        self._earlier: dict[str, int] = {}
        self._text: str | None = None
        self._final: tuple[str, str] | None = None
        self._started = False

    def __repr__(self) -> str:
        return f"Statechart({self.configuration!r})"

    # ---- reading the configuration ---------------------------------------------------

    @property
    def configuration(self) -> str:
        """The active leaf paths in declaration order joined by `` | `` (before the
        start: the configuration the start enters)."""
        if self._text is None:
            leaves = self._leaves(self.program.machine) if self._started else \
                _start_leaves(self.program.machine)
            self._text = " | ".join(leaves)
        return self._text

    def active(self) -> tuple[str, ...]:
        """The paths of every active state, outermost first, in declaration order."""
        return tuple(self._walk(self.program.machine))

    def activation(self, path: str) -> Activation | None:
        """The entry of the state at ``path`` while it is active, else ``None``."""
        state = self.program.states[path]
        activation = self._active.get(state.machine)
        return activation if activation is not None and activation.path == path else None

    def visits(self, path: str) -> int:
        """How often the state at ``path`` was entered since its machine was entered."""
        return self._visits.get(path, 0)

    def in_final(self, path: str, final: str, region: str | None = None) -> bool:
        """Whether the machine of the state at ``path`` (its region ``region`` for a
        parallel state) is active and in its final state ``final``."""
        machine = join(path, region) if region else path
        activation = self._active.get(machine)
        return (activation is not None and activation.path == join(machine, final)
                and self.program.states[activation.path].final)

    def done(self, path: str) -> bool:
        """Whether every region of the parallel state at ``path`` is in a final state."""
        if self.activation(path) is None:
            return False
        for machine in self.program.states[path].machines:
            activation = self._active.get(machine.path)
            if activation is None or not self.program.states[activation.path].final:
                return False
        return True

    @property
    def outcome(self) -> str | None:
        """The outcome of the mission machine's final state once entered, else ``None``."""
        return self._final[1] if self._final else None

    # ---- events ---------------------------------------------------------------------

    def raise_event(self, event: str, cycle: int) -> None:
        """Record that ``event`` was raised in ``cycle`` (never less than the last)."""
        latest = self._latest.get(event)
        if latest is not None and latest != cycle:
            self._earlier[event] = latest
        self._latest[event] = cycle

    def seen(self, event: str, owner: Activation, cycle: int) -> bool:
        """Whether ``event NAME`` holds in ``cycle`` for the clause owned by ``owner``:
        raised in a cycle from the owner's entry on, before ``cycle``."""
        raised = self._latest.get(event)
        if raised is not None and raised >= cycle:
            raised = self._earlier.get(event)
        return raised is not None and owner.cycle <= raised < cycle

    def handles_failure(self) -> bool:
        """Whether a clause checked in this configuration tests ``controller.failed``."""
        return self.program.handles_failure(self.active())

    # ---- one cycle ------------------------------------------------------------------

    def start(self, context) -> MacroStep:
        """Enter the mission's machine: its start state, and theirs inside, at once."""
        entered: list = []
        self._started = True
        self.enter_machine(self.program.machine, context, entered)
        step = MicroStep(None, self.program.start, "", (), tuple(entered))
        return self._macro(context, [step])

    def transitions(self, context) -> MacroStep:
        """Step 2 of a cycle: check the mission's machine (see :meth:`check`)."""
        steps: list = []
        self.check(self.program.machine, context, steps)
        return self._macro(context, steps)

    def during(self, context, machine: MachineProgram | None = None) -> None:
        """Step 3 of a cycle: the ``during`` blocks of the active states, outermost
        first."""
        machine = machine or self.program.machine
        state = self.program.states[self._active[machine.path].path]
        self._run(state.during, state.path, context, "during")
        for region in state.machines:
            self.during(context, region)

    def _macro(self, context, steps: list) -> MacroStep:
        final, outcome = self._final or (None, None)
        return MacroStep(context.cycle, context.time, tuple(steps), self.configuration,
                         final, outcome)

    # ---- the named functions ------------------------------------------------------------

    def check(self, machine: MachineProgram, context, steps: list) -> bool:
        """Select and fire the transitions of ``machine`` and of the machines inside its
        active state, innermost first; append a :class:`MicroStep` to ``steps`` for each.
        Return whether one fired."""
        owner = self._active[machine.path]
        state = self.program.states[owner.path]
        if state.final:
            return False
        fired = False
        for region in state.machines:
            fired = self.check(region, context, steps) or fired
        if fired:
            return True
        for clause in chain(state.clauses, machine.guards):
            try:
                holds = clause.test(context, owner)
            except Exception as error:  # named for whoever reports it
                raise StepFailed(f"condition '{clause.text}' of state '{owner.path}'") \
                    from error
            if holds:
                steps.append(self.fire(machine, owner, clause, context))
                return True
        return False

    def fire(self, machine: MachineProgram, owner: Activation, clause, context) -> MicroStep:
        """Take ``clause`` of ``machine`` from its active state ``owner``: exit it, run
        the clause's actions, enter the target."""
        target = machine.states[clause.target]
        if self.on_transition is not None:
            self.on_transition(owner.path, target.path, clause.text)
        exited: list = []
        entered: list = []
        self.exit(machine, context, exited)
        try:
            self._run(clause.actions, owner.path, context,
                      f"when {clause.text} -> {clause.target}")
        except StepFailed:      # the run ends where the failing action was: in the source
            self._active[machine.path] = owner
            self._text = None
            raise
        self.enter(machine, target, context, entered)
        return MicroStep(owner.path, target.path, clause.text, tuple(exited), tuple(entered))

    def exit(self, machine: MachineProgram, context, exited: list) -> None:
        """Leave the active state of ``machine``: the states inside it first (regions in
        reverse declaration order), then its ``exit`` block; append the paths left."""
        state = self.program.states[self._active[machine.path].path]
        for region in reversed(state.machines):
            if region.path in self._active:
                self.exit(region, context, exited)
        self._run(state.exit, state.path, context, "exit")
        del self._active[machine.path]
        self._text = None
        exited.append(state.path)

    def enter(self, machine: MachineProgram, state: StateProgram, context,
              entered: list) -> None:
        """Make ``state`` the active state of ``machine``: count the visit, run its
        ``enter`` block, then enter its machines in declaration order; append the paths
        entered."""
        self._active[machine.path] = Activation(state.path, context.time, context.cycle)
        self._text = None
        self._visits[state.path] = self._visits.get(state.path, 0) + 1
        entered.append(state.path)
        self._run(state.enter, state.path, context, "enter")
        for region in state.machines:
            self.enter_machine(region, context, entered)
        if state.final and machine is self.program.machine:
            self._final = (state.path, state.outcome)

    def enter_machine(self, machine: MachineProgram, context, entered: list) -> None:
        """Activate ``machine``: reset its ``visits`` counters, enter its start state."""
        for state in machine.states.values():
            self._visits[state.path] = 0
        self.enter(machine, machine.states[machine.start], context, entered)

    def _run(self, actions: list, path: str, context, block: str) -> None:
        """Run ``actions`` of ``block`` (``enter``, ``during``, ``exit`` or a clause)
        on behalf of the state at ``path`` (see :attr:`running`); an action that raises
        comes out as :class:`StepFailed` naming it."""
        if not actions:
            return
        self.running = path
        try:
            for index, action in enumerate(actions, 1):
                try:
                    action(context)
                except Exception as error:  # named for whoever reports it
                    where = (f"{block} action {index} of state '{path}'"
                             if block in ("enter", "during", "exit") else
                             f"action {index} of '{block}' in state '{path}'")
                    raise StepFailed(where) from error
        finally:
            self.running = None

    # ---- walking the configuration --------------------------------------------------------

    def _walk(self, machine: MachineProgram):
        activation = self._active.get(machine.path)
        if activation is None:
            return
        yield activation.path
        for region in self.program.states[activation.path].machines:
            yield from self._walk(region)

    def _leaves(self, machine: MachineProgram) -> list:
        activation = self._active.get(machine.path)
        if activation is None:
            return []
        state = self.program.states[activation.path]
        inner = [leaf for region in state.machines for leaf in self._leaves(region)]
        return inner or [state.path]


def _start_leaves(machine: MachineProgram) -> list:
    state = machine.states[machine.start]
    inner = [leaf for region in state.machines for leaf in _start_leaves(region)]
    return inner or [state.path]
