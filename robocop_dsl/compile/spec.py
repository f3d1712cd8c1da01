"""The compiled mission: plain typed specs, all values in SI, ready for a runtime.

Nothing here refers to the parser or to pinocchio: names are strings (bodies, joint
groups, tasks, states), numbers are floats [m, rad, s and their rates], vectors are
tuples. Spans point back into the mission file for run-time messages.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Union

import networkx as nx

from ..diagnostics import SourceFile, Span

# ---- values -----------------------------------------------------------------------


@dataclass(frozen=True)
class InterpolatorSpec:
    """``kind`` is ``otg``, ``linear``, ``cubic``, ``quintic`` or ``none`` (or a registered
    one); ``parameters`` in SI: otg ``max_velocity``, ``max_acceleration``, ``max_jerk``
    and ``target_velocity`` (tuples, one value per dof, one value for body tasks) and
    ``max_angular_velocity``, ``max_angular_acceleration``, ``max_angular_jerk``
    (floats [rad/s, rad/s^2, rad/s^3]); the others ``duration`` [s]."""

    kind: str
    parameters: dict[str, float | tuple[float, ...]] = field(default_factory=dict)


@dataclass(frozen=True)
class FeedbackSpec:
    """``proportional`` (``gain`` [1/s]) or ``pid`` (``kp``, ``ki``, ``kd``)."""

    kind: str
    parameters: dict[str, float] = field(default_factory=dict)


@dataclass(frozen=True)
class VectorTarget:
    """Joint positions [rad or m] or velocities, a position [m], rpy [rad] or a twist
    (vx, vy, vz [m/s], wx, wy, wz [rad/s]), depending on the task."""

    values: tuple[float, ...]


@dataclass(frozen=True)
class BodyTarget:
    """Track a body's pose; ``offset`` [m] is added to its position, in the task's
    reference frame."""

    body: str
    offset: tuple[float, float, float] | None = None


@dataclass(frozen=True)
class PoseTarget:
    """A pose in the task's reference frame; ``None`` parts are not constrained."""

    position: tuple[float, float, float] | None = None
    rpy: tuple[float, float, float] | None = None


@dataclass(frozen=True)
class CurrentTarget:
    """Hold the value the task has when the target is set (or the task enabled)."""


TargetSpec = Union[VectorTarget, BodyTarget, PoseTarget, CurrentTarget]


# ---- tasks and constraints ------------------------------------------------------------

@dataclass(frozen=True)
class TaskSpec:
    """A task: ``type`` from the catalogue (``joint_position``, ``body_pose``...) on a
    ``joint_group`` (joint tasks) or a ``body`` (body tasks), with its ``reference`` body
    (body tasks; ``"world"`` by default). ``gain`` [1/s] (a float, a tuple of one per
    dof / per axis, or ``None``: the feedback's) and ``weight`` can change while
    running; ``priority`` 0 is the highest level. ``controller`` is the qp_controller
    processor that runs it. ``tolerance`` tells when it counts as reached [SI]: one per
    dof for joint tasks, one per part for body tasks (position then orientation, linear
    then angular); ``enabled`` whether it is active from the start; ``options`` the
    parameters of its own type (a ``body_force`` task's ``axes`` and ``max_velocity``),
    in SI."""

    name: str
    type: str
    joint_group: str | None
    body: str | None
    reference: str | None
    target: TargetSpec
    interpolator: InterpolatorSpec
    feedback: FeedbackSpec
    priority: int
    weight: float
    gain: float | tuple[float, ...] | None
    dofs: int
    span: Span = field(compare=False)
    controller: str | None = None
    tolerance: tuple[float, ...] = ()
    enabled: bool = False
    options: dict = field(default_factory=dict)


@dataclass(frozen=True)
class ConstraintSpec:
    """A constraint, enabled from the start unless ``enabled`` is false.

    ``joint_kinematic`` on ``joint_group``: ``min_position``/``max_position`` (tuples,
    URDF limits by default), ``max_velocity`` (tuple, URDF by default),
    ``max_acceleration`` (tuple or ``None``: not limited). ``body_velocity`` on ``body``:
    ``reference`` (str), ``max_linear`` [m/s] and ``max_angular`` [rad/s] (a float
    bounds the norm, a 3-tuple each axis; ``None``: not limited). ``controller`` is the
    qp_controller processor that runs it.
    """

    name: str
    type: str
    joint_group: str | None
    body: str | None
    parameters: dict[str, object]
    span: Span = field(compare=False)
    controller: str | None = None
    enabled: bool = True


# ---- actions ---------------------------------------------------------------------------

@dataclass(frozen=True)
class EnableAction:
    names: tuple[str, ...]
    span: Span = field(compare=False)


@dataclass(frozen=True)
class DisableAction:
    names: tuple[str, ...]
    span: Span = field(compare=False)


@dataclass(frozen=True)
class ResetAction:
    """Restart the tasks' interpolators from the current state."""

    names: tuple[str, ...]
    span: Span = field(compare=False)


@dataclass(frozen=True)
class SetTargetAction:
    task: str
    target: TargetSpec
    span: Span = field(compare=False)


@dataclass(frozen=True)
class SetParameterAction:
    """Set ``gain``/``weight`` of a task or a limit of a constraint (SI; per-dof limits
    and per-dof / per-axis gains as tuples)."""

    owner: str
    parameter: str
    value: float | tuple[float, ...]
    span: Span = field(compare=False)


@dataclass(frozen=True)
class AttachAction:
    """From now on ``body`` moves rigidly with ``parent``."""

    body: str
    parent: str
    span: Span = field(compare=False)


@dataclass(frozen=True)
class DetachAction:
    body: str
    span: Span = field(compare=False)


@dataclass(frozen=True)
class EmitAction:
    event: str
    span: Span = field(compare=False)


@dataclass(frozen=True)
class LogAction:
    """``log TEXT``; ``fields`` are the vars its ``{NAME}`` print
    (:class:`~robocop_dsl.compile.variables.LogField`)."""

    text: str
    span: Span = field(compare=False)
    fields: tuple = ()


ActionSpec = Union[EnableAction, DisableAction, ResetAction, SetTargetAction,
                   SetParameterAction, AttachAction, DetachAction, EmitAction, LogAction]


# ---- conditions ------------------------------------------------------------------------

@dataclass(frozen=True)
class ReachedCondition:
    """The task's interpolator has finished and its error is within its tolerance."""

    task: str


@dataclass(frozen=True)
class InterpolatedCondition:
    """The task's interpolator has finished, whatever its error."""

    task: str


@dataclass(frozen=True)
class ControllerFailedCondition:
    """The QP had no solution this cycle."""


@dataclass(frozen=True)
class TaskMeasure:
    """``error`` (norm of the task error), ``position_error`` [m] or
    ``orientation_error`` [rad] of a task."""

    task: str
    field: str


@dataclass(frozen=True)
class ElapsedMeasure:
    """Time in the state that owns the clause [s] (for a machine's top-level clause, in
    that machine's active state)."""


@dataclass(frozen=True)
class VisitsMeasure:
    """How often the state at ``state`` (a path) was entered since its machine was
    entered, this entry included."""

    state: str


@dataclass(frozen=True)
class TimeMeasure:
    """Time since the mission started [s]."""


@dataclass(frozen=True)
class DistanceMeasure:
    """Distance between two bodies' origins [m]."""

    first: str
    second: str


@dataclass(frozen=True)
class ClearanceMeasure:
    """Distance between the collision geometries of two sets (bodies or joint groups) [m]."""

    first: str
    second: str


MeasureSpec = Union[TaskMeasure, ElapsedMeasure, TimeMeasure, DistanceMeasure,
                    ClearanceMeasure, VisitsMeasure]


@dataclass(frozen=True)
class CompareCondition:
    """``measure operator value``; ``operator`` is ``<``, ``<=``, ``>`` or ``>=``, value SI
    (a number, or a var's :class:`~robocop_dsl.compile.variables.VarValue`)."""

    measure: MeasureSpec
    operator: str
    value: object


@dataclass(frozen=True)
class EventCondition:
    """True from the cycle after ``event`` was raised until the state that owns the
    clause is left; a state entered after the event's cycle does not see it."""

    event: str


@dataclass(frozen=True)
class FinalCondition:
    """True while the machine of the state at ``state`` (a path), or its region
    ``region`` for a parallel state, is in its final state ``final``."""

    state: str
    final: str
    region: str | None = None


@dataclass(frozen=True)
class DoneCondition:
    """True while every region of the parallel state at ``state`` is in a final state."""

    state: str


@dataclass(frozen=True)
class NotCondition:
    operand: "ConditionSpec"


@dataclass(frozen=True)
class AllCondition:
    """``and`` of the operands."""

    operands: tuple["ConditionSpec", ...]


@dataclass(frozen=True)
class AnyCondition:
    """``or`` of the operands."""

    operands: tuple["ConditionSpec", ...]


ConditionSpec = Union[ReachedCondition, InterpolatedCondition, ControllerFailedCondition,
                      CompareCondition, EventCondition, FinalCondition, DoneCondition,
                      NotCondition, AllCondition, AnyCondition]


# ---- states, machines and the mission --------------------------------------------------

@dataclass(frozen=True)
class TransitionSpec:
    """``when condition -> target [{ actions }]``. ``target`` is a state of the same
    machine as the clause's source, by its local name; ``text`` is the condition as
    written (canonical); ``guard`` tells a machine's top-level clause from a state's
    own; ``actions`` run after the exits and before the enters."""

    condition: ConditionSpec
    target: str
    text: str
    guard: bool
    span: Span = field(compare=False)
    actions: tuple[ActionSpec, ...] = ()


@dataclass(frozen=True)
class StateSpec:
    """A state and its blocks.

    ``name`` is local to its machine, ``path`` names it from the mission's machine
    (``carry/up``; a parallel state's region adds its name: ``both/left/above``).
    ``transitions`` are the state's own clauses in writing order (none for final
    states); the machine's guards are on :class:`MachineSpec`. ``machines``: none for a
    simple state, one for a compound state or a behaviour instance (behaviour expanded),
    one per region, in declaration order, for a ``parallel`` state. ``outcome`` is
    ``"success"`` or ``"failure"`` for final states, else ``None``.
    """

    name: str
    enter: tuple[ActionSpec, ...]
    during: tuple[ActionSpec, ...]
    exit: tuple[ActionSpec, ...]
    transitions: tuple[TransitionSpec, ...]
    final: bool
    outcome: str | None
    span: Span = field(compare=False)
    path: str = ""
    machines: tuple["MachineSpec", ...] = ()
    parallel: bool = False

    @property
    def compound(self) -> bool:
        """Whether the state has a machine of its own (compound, instance, parallel)."""
        return bool(self.machines)


@dataclass(frozen=True)
class MachineSpec:
    """A state machine: the mission's (``path`` ``""``), a compound state's (the
    state's path) or a parallel state's region (``STATE_PATH/REGION``, ``region`` set).

    ``states`` by local name in declaration order; ``start`` the local name of the
    state it starts in; ``guards`` its own top-level clauses, checked after the active
    state's own clauses.
    """

    path: str
    states: dict[str, StateSpec]
    start: str
    guards: tuple[TransitionSpec, ...] = ()
    region: str | None = None

    def walk(self):
        """Every state of this machine and of the machines nested in it, parents
        first, in declaration order."""
        for state in self.states.values():
            yield state
            for machine in state.machines:
                yield from machine.walk()


@dataclass(frozen=True)
class MissionSpec:
    """A checked mission. ``world_path`` is the resolved world file; ``controllers``
    the qp_controller processors that run the tasks (several: cascaded, fastest first,
    see :mod:`robocop_dsl.check.controllers`); ``controller`` the first of them, which
    runs the state machine; ``machine`` the mission's state machine (nested machines
    inside its states, behaviour instances expanded); ``states`` every state of every
    level by path; ``graph`` the state graph (see :mod:`robocop_dsl.compile.state_graph`).
    Dicts keep declaration order."""

    name: str
    description: str | None
    world_path: Path
    controller: str
    constraints: dict[str, ConstraintSpec]
    tasks: dict[str, TaskSpec]
    machine: MachineSpec
    events: frozenset[str]
    graph: nx.DiGraph = field(compare=False, repr=False)
    source: SourceFile = field(compare=False, repr=False)
    controllers: tuple[str, ...] = ()
    variables: tuple = ()
    """The vars (:class:`~robocop_dsl.compile.variables.VarSpec`), one per instance of a
    behaviour that declares one."""

    @property
    def cascaded(self) -> bool:
        """Whether several controllers run the mission, each in its own thread."""
        return len(self.controllers) > 1

    @property
    def states(self) -> dict[str, StateSpec]:
        """Every state of every level, by path, parents first."""
        return {state.path: state for state in self.machine.walk()}

    @property
    def start(self) -> str:
        """The local name of the state the mission's machine starts in."""
        return self.machine.start

    @property
    def guards(self) -> tuple[TransitionSpec, ...]:
        """The mission's top-level clauses."""
        return self.machine.guards

    def state(self, path: str) -> StateSpec:
        return self.states[path]

    @property
    def final_states(self) -> list[str]:
        """The mission's own final states (they end the run)."""
        return [name for name, state in self.machine.states.items() if state.final]
