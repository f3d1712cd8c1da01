"""The mission syntax tree: frozen dataclasses, each with the source span it came from.

Spans do not take part in equality, so two trees that say the same thing compare equal
wherever they were written (the formatter's round trip relies on it). Numbers are kept
as written in the mission's units; converting them to SI is the checker's business.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Union

from ..diagnostics import Span

NO_SPAN = Span(0, 0, 0, 0)


@dataclass(frozen=True, slots=True)
class Node:
    """Base of every node: ``span`` locates it in the mission file."""

    span: Span = field(default=NO_SPAN, compare=False, repr=False, kw_only=True)


@dataclass(frozen=True, slots=True)
class Name(Node):
    """An identifier as written: a task, body, state, unit, parameter..."""

    text: str


# ---- values ------------------------------------------------------------------------

@dataclass(frozen=True, slots=True)
class Quantity(Node):
    """A number with an optional unit (``None``: SI)."""

    value: float
    unit: Name | None = None


@dataclass(frozen=True, slots=True)
class NameElement(Node):
    """A name inside a vector: a constant or a behaviour parameter, ``-NAME`` when
    ``negative``."""

    name: Name
    negative: bool = False


@dataclass(frozen=True, slots=True)
class Vector(Node):
    """``[a, b, c] unit``: numbers sharing one optional unit; elements may be names
    (:class:`NameElement`) until the checker substitutes their values. The unit
    applies to the bare numbers only."""

    values: tuple[float | NameElement, ...]
    unit: Name | None = None


@dataclass(frozen=True, slots=True)
class Reference(Node):
    """A bare name used as a value: a body, ``world``, ``current``, ``none``."""

    name: Name


@dataclass(frozen=True, slots=True)
class Offset(Node):
    """``BODY offset VECTOR``: a point displaced from a body; the vector may be named
    (a constant or a behaviour parameter, :class:`Reference`) until the checker binds it."""

    body: Name
    offset: Union[Vector, "Reference"]


@dataclass(frozen=True, slots=True)
class Argument(Node):
    """One argument of a call: ``name = value`` or a positional ``value``."""

    name: Name | None
    value: "Value"


@dataclass(frozen=True, slots=True)
class Call(Node):
    """``kind(arguments)``: an interpolator, a feedback law or ``pose(...)``."""

    kind: Name
    arguments: tuple[Argument, ...] = ()


@dataclass(frozen=True, slots=True)
class String(Node):
    """A double-quoted string, without its quotes and with escapes resolved."""

    text: str


Value = Union[Quantity, Vector, Reference, Offset, Call, String]


@dataclass(frozen=True, slots=True)
class Parameter(Node):
    """``name = value`` inside a task or constraint declaration."""

    name: Name
    value: Value


# ---- conditions --------------------------------------------------------------------

@dataclass(frozen=True, slots=True)
class Member(Node):
    """``owner.field``: ``arms.reached``, ``left_tool.error``, ``controller.failed``,
    ``pick.arrived`` (a final of a state's machine), ``both.done``, ``pick.visits``;
    ``owner.region.field`` (``both.left.missed``) names a region's final."""

    owner: Name
    field: Name
    region: Name | None = None


@dataclass(frozen=True, slots=True)
class Elapsed(Node):
    """Time spent in the current state [s]."""


@dataclass(frozen=True, slots=True)
class Time(Node):
    """Time since the mission started [s]."""


@dataclass(frozen=True, slots=True)
class Distance(Node):
    """``distance(A, B)``: distance between the origins of two bodies [m]."""

    first: Name
    second: Name


@dataclass(frozen=True, slots=True)
class Clearance(Distance):
    """``clearance(A, B)``: distance between the collision geometries of two sets (a
    body, or a joint group for every body its joints move) [m]."""


Measure = Union[Member, Elapsed, Time, Distance, Clearance, "Wrench", "Variable"]


@dataclass(frozen=True, slots=True)
class Wrench(Node):
    """``force(BODY)`` or ``torque(BODY)`` [N, N m], the norm or, with ``axis``, one
    world component, of what the body exerts on the environment (its force sensor)."""

    torque: bool
    body: Name
    axis: Name | None = None


@dataclass(frozen=True, slots=True)
class Variable(Node):
    """A bare name read as a value: a ``var`` (or, in an expression, a constant)."""

    name: Name


@dataclass(frozen=True, slots=True)
class Contact(Node):
    """``contact(A, B)``: whether the physics has a contact between two bodies or sets."""

    first: Name
    second: Name


@dataclass(frozen=True, slots=True)
class Binary(Node):
    """``LEFT OP RIGHT`` with ``OP`` one of ``+ - * /``."""

    operator: str
    left: "Expression"
    right: "Expression"


@dataclass(frozen=True, slots=True)
class Negative(Node):
    """``-OPERAND``."""

    operand: "Expression"


Expression = Union[Quantity, "Variable", "Member", "Wrench", "Distance", "Elapsed", "Time",
                   Binary, Negative]


@dataclass(frozen=True, slots=True)
class Comparison(Node):
    """``measure OP quantity`` with OP one of ``< <= > >=``; the quantity may be a name
    (a constant or a behaviour parameter, :class:`Reference`) until the checker binds it."""

    measure: Measure
    operator: str
    quantity: Quantity | Reference


@dataclass(frozen=True, slots=True)
class EventCondition(Node):
    """``event NAME``: true in the cycle after the event was emitted."""

    event: Name


@dataclass(frozen=True, slots=True)
class Not(Node):
    operand: "Condition"


@dataclass(frozen=True, slots=True)
class And(Node):
    operands: tuple["Condition", ...]


@dataclass(frozen=True, slots=True)
class Or(Node):
    operands: tuple["Condition", ...]


Condition = Union[Member, Comparison, EventCondition, Contact, Not, And, Or]


# ---- actions -----------------------------------------------------------------------

@dataclass(frozen=True, slots=True)
class Enable(Node):
    names: tuple[Name, ...]


@dataclass(frozen=True, slots=True)
class Disable(Node):
    names: tuple[Name, ...]


@dataclass(frozen=True, slots=True)
class Reset(Node):
    """Restart the interpolators of tasks from the current state."""

    names: tuple[Name, ...]


@dataclass(frozen=True, slots=True)
class Assign(Node):
    """``owner.field = value``: set a task's target, gain, weight..."""

    owner: Name
    field: Name
    value: Value


@dataclass(frozen=True, slots=True)
class SetVar(Node):
    """``NAME = EXPRESSION``: a new value for a ``var``."""

    name: Name
    value: Expression


@dataclass(frozen=True, slots=True)
class Attach(Node):
    """``attach BODY to PARENT``: the body moves rigidly with the parent from now on."""

    body: Name
    parent: Name


@dataclass(frozen=True, slots=True)
class Detach(Node):
    body: Name


@dataclass(frozen=True, slots=True)
class Emit(Node):
    event: Name


@dataclass(frozen=True, slots=True)
class Log(Node):
    text: str


Action = Union[Enable, Disable, Reset, Assign, SetVar, Attach, Detach, Emit, Log]


# ---- declarations ------------------------------------------------------------------

@dataclass(frozen=True, slots=True)
class MissionHeader(Node):
    name: Name
    description: str | None = None


@dataclass(frozen=True, slots=True)
class WorldDecl(Node):
    """``world "FILE"``: the world file, relative to the mission, then the robots path."""

    path: String


@dataclass(frozen=True, slots=True)
class ControllerDecl(Node):
    name: Name


@dataclass(frozen=True, slots=True)
class TaskDecl(Node):
    """``task NAME: TYPE(ARGS) { PARAMETERS }``."""

    name: Name
    kind: Name
    arguments: tuple[Name, ...]
    parameters: tuple[Parameter, ...] = ()


@dataclass(frozen=True, slots=True)
class ConstraintDecl(Node):
    """``constraint NAME: TYPE(ARGS) { PARAMETERS }``."""

    name: Name
    kind: Name
    arguments: tuple[Name, ...]
    parameters: tuple[Parameter, ...] = ()


@dataclass(frozen=True, slots=True)
class EventDecl(Node):
    """``event NAME "description"``: an event raised from outside the mission (an
    operator, ``runner.emit(NAME)`` from Python)."""

    name: Name
    description: str | None = None


@dataclass(frozen=True, slots=True)
class StartDecl(Node):
    state: Name


@dataclass(frozen=True, slots=True)
class ActionBlock(Node):
    """``enter``, ``during`` or ``exit`` followed by its actions."""

    kind: str
    actions: tuple[Action, ...] = ()


@dataclass(frozen=True, slots=True)
class Transition(Node):
    """``when CONDITION -> STATE [{ ACTIONS }]``, inside a state or at the top level of
    a machine (a guard); ``actions`` run after the source's ``exit`` blocks and before
    the target's ``enter`` blocks."""

    condition: Condition
    target: Name
    actions: tuple[Action, ...] = ()


StatePart = Union[ActionBlock, Transition]


@dataclass(frozen=True, slots=True)
class Instance(Node):
    """``NAME(ARGUMENTS)`` after ``state S:`` or ``region R:``: a behaviour instance."""

    behavior: Name
    arguments: tuple[Argument, ...] = ()


@dataclass(frozen=True, slots=True)
class VarDecl(Node):
    """``var NAME: KIND [= EXPRESSION]``: a value that changes at run time, of a kind
    (``count``, ``scalar``, ``position`` or a dimension such as ``length``); one per
    behaviour instance when a behaviour declares it."""

    name: Name
    kind: Name
    value: Expression | None = None


@dataclass(frozen=True, slots=True)
class Machine(Node):
    """A state machine's body: states and finals, an optional ``start`` and its own
    top-level ``when`` clauses (guards, checked after the active state's own), in
    source order."""

    items: tuple[Union["StateDecl", StartDecl, Transition, VarDecl], ...] = ()

    @property
    def variables(self) -> list[VarDecl]:
        return [i for i in self.items if isinstance(i, VarDecl)]

    @property
    def states(self) -> list["StateDecl"]:
        return [i for i in self.items if isinstance(i, StateDecl)]

    @property
    def guards(self) -> list[Transition]:
        return [i for i in self.items if isinstance(i, Transition)]

    @property
    def start(self) -> StartDecl | None:
        return next((i for i in self.items if isinstance(i, StartDecl)), None)


@dataclass(frozen=True, slots=True)
class Region(Node):
    """A machine inside a state. A parallel state's ``region NAME { ... }`` (``machine``)
    or ``region NAME: BEHAVIOR(ARGS)`` (``instance``), or, with ``name`` ``None``, the
    machine of a compound state. After the checker expands behaviour instances, an
    instance region has both ``instance`` and its bound ``machine``."""

    name: Name | None
    machine: Machine | None = None
    instance: Instance | None = None


@dataclass(frozen=True, slots=True)
class StateDecl(Node):
    """``state NAME { ... }`` or ``final NAME[: OUTCOME] [{ ... }]``.

    ``parts`` are the state's own blocks and clauses in order. A compound state has one
    unnamed region (its inline machine); ``state S: B(ARGS) { ... }`` has ``instance``
    (and, once expanded by the checker, the bound behaviour machine as its one unnamed
    region); ``state S: parallel { ... }`` has ``parallel`` and named regions.
    """

    name: Name
    parts: tuple[StatePart, ...] = ()
    final: bool = False
    outcome: Name | None = None
    instance: Instance | None = None
    parallel: bool = False
    regions: tuple[Region, ...] = ()

    @property
    def blocks(self) -> tuple[ActionBlock, ...]:
        return tuple(p for p in self.parts if isinstance(p, ActionBlock))

    @property
    def transitions(self) -> tuple[Transition, ...]:
        return tuple(p for p in self.parts if isinstance(p, Transition))

    def block(self, kind: str) -> ActionBlock | None:
        """The first ``enter``/``during``/``exit`` block, if any."""
        return next((b for b in self.blocks if b.kind == kind), None)


@dataclass(frozen=True, slots=True)
class LibraryHeader(Node):
    """``library NAME "description"``: a file of declarations meant to be imported."""

    name: Name
    description: str | None = None


@dataclass(frozen=True, slots=True)
class Import(Node):
    """``import "FILE"``: declarations of another file, beside this one, then the robots
    path."""

    path: String


@dataclass(frozen=True, slots=True)
class Let(Node):
    """``let NAME = VALUE``: a named constant."""

    name: Name
    value: Value


@dataclass(frozen=True, slots=True)
class BehaviorParam(Node):
    """``NAME: KIND [= DEFAULT]`` in a behaviour's parameter list; ``kind`` is ``task``,
    ``constraint``, ``body``, ``joint_group``, ``event``, ``target`` or a dimension
    (``length``, ``angle``, ``duration``...)."""

    name: Name
    kind: Name
    default: Value | None = None


@dataclass(frozen=True, slots=True)
class BehaviorDecl(Node):
    """``behavior NAME(PARAMETERS) { MACHINE }``: a reusable sub-machine whose finals are
    its outcomes."""

    name: Name
    parameters: tuple[BehaviorParam, ...]
    machine: Machine


Item = Union[MissionHeader, LibraryHeader, Import, Let, BehaviorDecl, WorldDecl,
             ControllerDecl, TaskDecl, ConstraintDecl, EventDecl, StartDecl, StateDecl,
             Transition, VarDecl]


@dataclass(frozen=True, slots=True)
class Mission(Node):
    """A whole mission file: its items in source order."""

    items: tuple[Item, ...] = ()

    def of_type(self, kind: type) -> list:
        return [item for item in self.items if isinstance(item, kind)]

    @property
    def tasks(self) -> list[TaskDecl]:
        return self.of_type(TaskDecl)

    @property
    def constraints(self) -> list[ConstraintDecl]:
        return self.of_type(ConstraintDecl)

    @property
    def states(self) -> list[StateDecl]:
        return self.of_type(StateDecl)

    @property
    def guards(self) -> list[Transition]:
        """The top-level ``when`` clauses, checked in every state after its own."""
        return self.of_type(Transition)

    @property
    def machine(self) -> Machine:
        """The mission's own state machine: its top-level states, start and guards."""
        return Machine(tuple(i for i in self.items
                             if isinstance(i, (StateDecl, StartDecl, Transition, VarDecl))),
                       span=self.span)

    @property
    def behaviors(self) -> list[BehaviorDecl]:
        return self.of_type(BehaviorDecl)

    def first(self, kind: type):
        """The first item of ``kind``, or ``None``."""
        return next((item for item in self.items if isinstance(item, kind)), None)
