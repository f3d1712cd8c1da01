"""Turn a checked mission syntax tree into specs (SI values, defaults filled in).

The input must have passed :func:`robocop_dsl.check.check_mission` without errors;
this module converts and does not check again.
"""

from __future__ import annotations

from pathlib import Path

import networkx as nx

from ..check.context import WorldNames
from ..check.controllers import controller_of, mission_controllers
from ..check.values import to_si, vector_to_si
from ..diagnostics import SourceFile
from ..lang import ast
from ..lang.catalogue import (BODY, CONSTRAINTS, FEEDBACKS, INTEGER, INTERPOLATORS,
                              JOINT_GROUP, PER_DOF, SCALAR, TASKS, Kind, Registry)
from ..lang.formatter import format_condition
from . import spec

_SPACE_DOFS = {"position": 3, "orientation": 3, "pose": 6, "twist": 6, "gaze": 2}


def compile_mission(mission: ast.Mission, source: SourceFile, world, world_path: Path,
                    start: str, graph: nx.DiGraph) -> spec.MissionSpec:
    """The :class:`~spec.MissionSpec` of a mission that checked without errors."""
    names = WorldNames(world)
    header = mission.first(ast.MissionHeader)
    controllers = mission_controllers(names, mission)
    constraints = {d.name.text: _constraint(d, names, controller_of(names, controllers, d))
                   for d in mission.constraints}
    tasks = {d.name.text: _task(d, names, controller_of(names, controllers, d))
             for d in mission.tasks}
    converter = _Converter(mission, names)
    guards = tuple(converter.transition(g, guard=True) for g in mission.guards)
    states = {s.name.text: converter.state(s, guards) for s in mission.states}
    events = frozenset([a.event.text for s in mission.states for b in s.blocks
                        for a in b.actions if isinstance(a, ast.Emit)]
                       + [e.name.text for e in mission.of_type(ast.EventDecl)])
    return spec.MissionSpec(
        name=header.name.text, description=header.description, world_path=world_path,
        controller=controllers[0], constraints=constraints, tasks=tasks, states=states,
        start=start, guards=guards, events=events, graph=graph, source=source,
        controllers=tuple(controllers))


def _parameters(decl) -> dict[str, ast.Value]:
    return {p.name.text: p.value for p in decl.parameters}


def _subject(decl, names: WorldNames, registry: Registry):
    kind = registry.get(decl.kind.text)
    subject = decl.arguments[0].text
    joints = names.joints(subject) if kind.subject == JOINT_GROUP else None
    return kind, subject, joints


def _task(decl: ast.TaskDecl, names: WorldNames, controller: str) -> spec.TaskSpec:
    kind, subject, joints = _subject(decl, names, TASKS)
    given = _parameters(decl)
    dofs = joints.dofs if joints else _SPACE_DOFS[kind.space]
    per_dof = dofs if joints else 1
    gain = given.get("gain")
    return spec.TaskSpec(
        name=decl.name.text, type=kind.name,
        joint_group=subject if joints else None, body=None if joints else subject,
        reference=(given["reference"].name.text if "reference" in given else "world")
        if not joints else None,
        target=target_spec(given.get("target"), kind, dofs),
        interpolator=spec.InterpolatorSpec(*_call(given.get("interpolator"), INTERPOLATORS,
                                                  "none", per_dof)),
        feedback=spec.FeedbackSpec(*_call(given.get("feedback"), FEEDBACKS, "proportional",
                                          per_dof)),
        priority=int(given["priority"].value) if "priority" in given else 0,
        weight=to_si(given["weight"]) if "weight" in given else 1.0,
        gain=to_si(gain) if gain is not None else None,
        dofs=dofs, span=decl.span, controller=controller)


def _constraint(decl: ast.ConstraintDecl, names: WorldNames,
                controller: str) -> spec.ConstraintSpec:
    kind, subject, joints = _subject(decl, names, CONSTRAINTS)
    given = _parameters(decl)
    dofs = joints.dofs if joints else 1
    values: dict[str, object] = {}
    for parameter in kind.parameters:
        if parameter.name in given:
            values[parameter.name] = convert(given[parameter.name], parameter.kind, dofs)
        else:
            values[parameter.name] = parameter.default
    if joints is not None:
        defaults = {"min_position": joints.lower, "max_position": joints.upper,
                    "max_velocity": joints.max_velocity}
        for name, default in defaults.items():
            if name in values and values[name] is None:
                values[name] = default
    return spec.ConstraintSpec(decl.name.text, kind.name, subject if joints else None,
                               None if joints else subject, values, decl.span, controller)


def convert(value: ast.Value, kind: str, dofs: int):
    """A parameter value in SI: float, tuple (per dof), int or a body name."""
    if kind == SCALAR:
        return to_si(value)
    if kind == PER_DOF:
        if isinstance(value, ast.Quantity):
            return (to_si(value),) * dofs
        return vector_to_si(value)
    if kind == INTEGER:
        return int(value.value)
    if kind == BODY:
        return value.name.text
    raise ValueError(f"no conversion for parameters of kind {kind!r}")


def _call(value: ast.Value | None, registry: Registry, default: str, dofs: int):
    if value is None:
        kind_name, arguments = default, ()
    elif isinstance(value, ast.Reference):
        kind_name, arguments = value.name.text, ()
    else:
        kind_name, arguments = value.kind.text, value.arguments
    kind: Kind = registry.get(kind_name)
    result = {}
    for index, argument in enumerate(arguments):
        parameter = kind.parameter(argument.name.text) if argument.name \
            else kind.parameters[index]
        result[parameter.name] = convert(argument.value, parameter.kind, dofs)
    for parameter in kind.parameters:
        if parameter.name not in result and parameter.default is not None:
            result[parameter.name] = parameter.default
    return kind.name, result


def target_spec(value: ast.Value | None, kind: Kind, dofs: int) -> spec.TargetSpec:
    """The spec of a checked target value for a task of type ``kind``."""
    if value is None or (isinstance(value, ast.Reference) and value.name.text == "current"):
        return spec.CurrentTarget()
    if isinstance(value, ast.Reference):
        return spec.BodyTarget(value.name.text)
    if isinstance(value, ast.Offset):
        return spec.BodyTarget(value.body.text, vector_to_si(value.offset))
    if isinstance(value, ast.Call):
        parts = {}
        for index, argument in enumerate(value.arguments):
            name = argument.name.text if argument.name else ("position", "rpy")[index]
            parts[name] = vector_to_si(argument.value)
        return spec.PoseTarget(parts.get("position"), parts.get("rpy"))
    if isinstance(value, ast.Quantity):
        return spec.VectorTarget((to_si(value),) * dofs)
    return spec.VectorTarget(vector_to_si(value))


class _Converter:
    """Converts states, actions and conditions, knowing the mission's tasks."""

    def __init__(self, mission: ast.Mission, names: WorldNames):
        self.tasks = {d.name.text: d for d in mission.tasks}
        self.constraints = {d.name.text: d for d in mission.constraints}
        self.names = names

    def state(self, state: ast.StateDecl, guards) -> spec.StateSpec:
        blocks = {kind: tuple(self.action(a) for a in block.actions) if block else ()
                  for kind in ("enter", "during", "exit")
                  for block in (state.block(kind),)}
        transitions = () if state.final else tuple(
            self.transition(t, guard=False) for t in state.transitions) + guards
        outcome = (state.outcome.text if state.outcome else "success") if state.final else None
        return spec.StateSpec(state.name.text, blocks["enter"], blocks["during"],
                              blocks["exit"], transitions, state.final, outcome, state.span)

    def transition(self, transition: ast.Transition, guard: bool) -> spec.TransitionSpec:
        return spec.TransitionSpec(self.condition(transition.condition),
                                   transition.target.text,
                                   format_condition(transition.condition), guard,
                                   transition.span)

    def action(self, action: ast.Action) -> spec.ActionSpec:
        span = action.span
        if isinstance(action, ast.Enable):
            return spec.EnableAction(tuple(n.text for n in action.names), span)
        if isinstance(action, ast.Disable):
            return spec.DisableAction(tuple(n.text for n in action.names), span)
        if isinstance(action, ast.Reset):
            return spec.ResetAction(tuple(n.text for n in action.names), span)
        if isinstance(action, ast.Assign):
            return self._assign(action)
        if isinstance(action, ast.Attach):
            return spec.AttachAction(action.body.text, action.parent.text, span)
        if isinstance(action, ast.Detach):
            return spec.DetachAction(action.body.text, span)
        if isinstance(action, ast.Emit):
            return spec.EmitAction(action.event.text, span)
        return spec.LogAction(action.text, span)

    def _assign(self, action: ast.Assign) -> spec.ActionSpec:
        owner = action.owner.text
        decl = self.tasks.get(owner) or self.constraints.get(owner)
        registry = TASKS if owner in self.tasks else CONSTRAINTS
        kind, _, joints = _subject(decl, self.names, registry)
        if action.field.text == "target":
            dofs = joints.dofs if joints else _SPACE_DOFS[kind.space]
            return spec.SetTargetAction(owner, target_spec(action.value, kind, dofs),
                                        action.span)
        parameter = kind.parameter(action.field.text)
        value = convert(action.value, parameter.kind, joints.dofs if joints else 1)
        return spec.SetParameterAction(owner, parameter.name, value, action.span)

    def condition(self, condition: ast.Condition) -> spec.ConditionSpec:
        if isinstance(condition, ast.Or):
            return spec.AnyCondition(tuple(map(self.condition, condition.operands)))
        if isinstance(condition, ast.And):
            return spec.AllCondition(tuple(map(self.condition, condition.operands)))
        if isinstance(condition, ast.Not):
            return spec.NotCondition(self.condition(condition.operand))
        if isinstance(condition, ast.EventCondition):
            return spec.EventCondition(condition.event.text)
        if isinstance(condition, ast.Comparison):
            return spec.CompareCondition(self.measure(condition.measure),
                                         condition.operator, to_si(condition.quantity))
        if condition.owner.text == "controller":
            return spec.ControllerFailedCondition()
        return spec.ReachedCondition(condition.owner.text)

    @staticmethod
    def measure(measure: ast.Measure) -> spec.MeasureSpec:
        if isinstance(measure, ast.Elapsed):
            return spec.ElapsedMeasure()
        if isinstance(measure, ast.Time):
            return spec.TimeMeasure()
        if isinstance(measure, ast.Distance):
            return spec.DistanceMeasure(measure.first.text, measure.second.text)
        return spec.TaskMeasure(measure.owner.text, measure.field.text)
