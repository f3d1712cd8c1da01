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
from ..lang.catalogue import (AXES, BODY, COLLISION_SETS, CONSTRAINTS, FEEDBACKS, INTEGER,
                              INTERPOLATORS, JOINT_GROUP, NORM_OR_AXES, PER_AXIS, PER_DOF,
                              SCALAR, SPACE_AXES, SWITCH, TASKS, Kind, Registry)
from ..lang.formatter import format_condition
from . import spec
from . import variables as v
from .state_graph import join, machine_start, region_machine
from .tolerance import tolerance_spec


def compile_mission(mission: ast.Mission, source: SourceFile, world, world_path: Path,
                    graph: nx.DiGraph) -> spec.MissionSpec:
    """The :class:`~spec.MissionSpec` of a mission that checked without errors.

    ``mission`` is the checker's expanded tree: constants and behaviour parameters
    substituted, every behaviour instance bound to its machine (see
    :mod:`robocop_dsl.check.expand`)."""
    names = WorldNames(world)
    header = mission.first(ast.MissionHeader)
    controllers = mission_controllers(names, mission)
    constraints = {d.name.text: _constraint(d, names, controller_of(names, controllers, d))
                   for d in mission.constraints}
    tasks = {d.name.text: _task(d, names, controller_of(names, controllers, d))
             for d in mission.tasks}
    converter = _Converter(mission, names)
    machine = converter.machine(mission.machine, "", None, ())
    events = frozenset(converter.emitted | {e.name.text for e in mission.of_type(ast.EventDecl)})
    return spec.MissionSpec(
        name=header.name.text, description=header.description, world_path=world_path,
        controller=controllers[0], constraints=constraints, tasks=tasks, machine=machine,
        events=events, graph=graph, source=source, controllers=tuple(controllers),
        variables=tuple(converter.variables))


TASK_OPTIONS = ("axes", "max_velocity")
"""Parameters some task types have of their own, passed to the task as they are."""


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
    dofs = joints.dofs if joints else SPACE_AXES[kind.space]
    per_dof = dofs if joints else 1
    gain = given.get("gain")
    enabled = given.get("enabled")
    return spec.TaskSpec(
        name=decl.name.text, type=kind.name,
        joint_group=subject if joints else None, body=None if joints else subject,
        reference=(given["reference"].name.text if "reference" in given else "world")
        if not joints else None,
        target=(target_spec(given["target"], kind, dofs) if "target" in given
                else _default_target(kind)),
        interpolator=spec.InterpolatorSpec(*_call(given.get("interpolator"), INTERPOLATORS,
                                                  "none", per_dof)),
        feedback=spec.FeedbackSpec(*_call(given.get("feedback"), FEEDBACKS, "proportional",
                                          per_dof)),
        priority=int(given["priority"].value) if "priority" in given else 0,
        weight=to_si(given["weight"]) if "weight" in given else 1.0,
        gain=convert(gain, PER_AXIS, dofs) if gain is not None else None,
        dofs=dofs, span=decl.span, controller=controller,
        tolerance=tolerance_spec(given.get("tolerance"), kind.space, joints),
        enabled=convert(enabled, SWITCH, dofs) if enabled is not None else False,
        options={p.name: convert(given[p.name], p.kind, dofs) if p.name in given
                 else p.default for p in kind.parameters if p.name in TASK_OPTIONS})


def _default_target(kind: Kind) -> spec.TargetSpec:
    """A task's target when its declaration gives none: its kind's default (a
    ``body_force`` task's zero force), else ``current``."""
    default = kind.parameter("target").default if kind.parameter("target") else None
    return spec.VectorTarget(tuple(default)) if isinstance(default, tuple) \
        else spec.CurrentTarget()


def _constraint(decl: ast.ConstraintDecl, names: WorldNames,
                controller: str) -> spec.ConstraintSpec:
    kind, subject, joints = _subject(decl, names, CONSTRAINTS)
    given = _parameters(decl)
    dofs = joints.dofs if joints else 1
    values: dict[str, object] = {}
    enabled = given.get("enabled")
    for parameter in kind.parameters:
        if parameter.kind == SWITCH:
            continue
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
    if kind.subject == COLLISION_SETS:
        values["other"] = decl.arguments[1].text
    return spec.ConstraintSpec(decl.name.text, kind.name, subject if joints else None,
                               None if joints else subject, values, decl.span, controller,
                               convert(enabled, SWITCH, dofs) if enabled is not None else True)


def convert(value: ast.Value, kind: str, dofs: int):
    """A parameter value in SI: float, tuple (per dof; per axis for ``PER_AXIS`` and
    ``NORM_OR_AXES`` vectors, whose single number stays a float), int, bool, a body
    name or, for ``AXES``, the indices (0, 1, 2 for x, y, z) of the axes listed."""
    if kind == SCALAR:
        return to_si(value)
    if kind == PER_DOF:
        if isinstance(value, ast.Quantity):
            return (to_si(value),) * dofs
        return vector_to_si(value)
    if kind in (PER_AXIS, NORM_OR_AXES):
        return to_si(value) if isinstance(value, ast.Quantity) else vector_to_si(value)
    if kind == SWITCH:
        return value.name.text == "true"
    if kind == INTEGER:
        return int(value.value)
    if kind == BODY:
        return value.name.text
    if kind == AXES:
        return tuple("xyz".index(element.name.text) for element in value.values)
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


def target_spec(value: ast.Value | None, kind: Kind, dofs: int,
                vector_to_si=vector_to_si) -> spec.TargetSpec:
    """The spec of a checked target value for a task of type ``kind``; ``vector_to_si``
    converts its vectors (an action's may hold vars)."""
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
    """Converts machines, states, actions and conditions, knowing the mission's tasks.

    ``scope`` is the chain of machines a clause can see, innermost first: each a dict
    of local state name to ``(path, declaration)``."""

    def __init__(self, mission: ast.Mission, names: WorldNames):
        self.tasks = {d.name.text: d for d in mission.tasks}
        self.constraints = {d.name.text: d for d in mission.constraints}
        self.names = names
        self.emitted: set[str] = set()
        self.variables: list[v.VarSpec] = []
        self.vars = v.VarScope()
        self.mission_vars = v.VarScope()

    def machine(self, machine: ast.Machine, path: str, region: str | None,
                scope: tuple, instance: bool = False) -> spec.MachineSpec:
        prefix = path
        local = {s.name.text: (join(prefix, s.name.text), s) for s in machine.states}
        scope = (local, *scope)
        outer = self.vars
        self.vars = self.vars.inner(machine, path, self.mission_vars if instance else outer)
        if not path:
            self.mission_vars = self.vars
        try:
            self.variables += v.var_specs(machine, path, self.vars,
                                          lambda node: self.measure(node, scope))
            states = {name: self.state(decl, state_path, scope)
                      for name, (state_path, decl) in local.items()}
            guards = tuple(self.transition(g, True, scope) for g in machine.guards)
        finally:
            self.vars = outer
        return spec.MachineSpec(path, states, machine_start(machine), guards, region)

    def state(self, state: ast.StateDecl, path: str, scope: tuple) -> spec.StateSpec:
        blocks = {kind: tuple(self.action(a, scope) for a in block.actions) if block else ()
                  for kind in ("enter", "during", "exit")
                  for block in (state.block(kind),)}
        transitions = () if state.final else tuple(
            self.transition(t, False, scope) for t in state.transitions)
        outcome = (state.outcome.text if state.outcome else "success") if state.final else None
        machines = tuple(
            self.machine(region_machine(r), join(path, r.name.text) if r.name else path,
                         r.name.text if r.name else None, scope, r.instance is not None)
            for r in state.regions)
        return spec.StateSpec(state.name.text, blocks["enter"], blocks["during"],
                              blocks["exit"], transitions, state.final, outcome, state.span,
                              path=path, machines=machines, parallel=state.parallel)

    def transition(self, transition: ast.Transition, guard: bool,
                   scope: tuple) -> spec.TransitionSpec:
        return spec.TransitionSpec(self.condition(transition.condition, scope),
                                   transition.target.text,
                                   format_condition(transition.condition), guard,
                                   transition.span,
                                   tuple(self.action(a, scope) for a in transition.actions))

    def action(self, action: ast.Action, scope: tuple) -> spec.ActionSpec:
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
            self.emitted.add(action.event.text)
            return spec.EmitAction(action.event.text, span)
        if isinstance(action, ast.SetVar):
            return v.SetVarAction(self.vars[action.name.text],
                                  v.expression(action.value, self.vars,
                                               lambda node: self.measure(node, scope)), span)
        units = {var.name: var.unit for var in self.variables}
        return spec.LogAction(action.text, span, v.log_fields(action.text, self.vars, units))

    def _assign(self, action: ast.Assign) -> spec.ActionSpec:
        owner = action.owner.text
        decl = self.tasks.get(owner) or self.constraints.get(owner)
        registry = TASKS if owner in self.tasks else CONSTRAINTS
        kind, _, joints = _subject(decl, self.names, registry)
        if action.field.text == "target":
            dofs = joints.dofs if joints else SPACE_AXES[kind.space]
            return spec.SetTargetAction(owner, target_spec(action.value, kind, dofs,
                                                           self._vector), action.span)
        parameter = kind.parameter(action.field.text)
        value = convert(action.value, parameter.kind, joints.dofs if joints else 1)
        return spec.SetParameterAction(owner, parameter.name, value, action.span)

    def _vector(self, vector: ast.Vector) -> tuple:
        """A target's vector in SI, its vars as :class:`~.variables.VarValue`."""
        scale = vector_to_si(ast.Vector((1.0,), vector.unit))[0]
        return tuple(v.VarValue(self.vars[e.name.text]) if isinstance(e, ast.NameElement)
                     and not e.negative else
                     v.Negated(v.VarValue(self.vars[e.name.text]))
                     if isinstance(e, ast.NameElement) else e * scale
                     for e in vector.values)

    def condition(self, condition: ast.Condition, scope: tuple) -> spec.ConditionSpec:
        if isinstance(condition, ast.Or):
            return spec.AnyCondition(tuple(self.condition(c, scope)
                                           for c in condition.operands))
        if isinstance(condition, ast.And):
            return spec.AllCondition(tuple(self.condition(c, scope)
                                           for c in condition.operands))
        if isinstance(condition, ast.Not):
            return spec.NotCondition(self.condition(condition.operand, scope))
        if isinstance(condition, ast.EventCondition):
            return spec.EventCondition(condition.event.text)
        if isinstance(condition, ast.Contact):
            return v.ContactCondition(condition.first.text, condition.second.text)
        if isinstance(condition, ast.Comparison):
            value = condition.quantity
            return spec.CompareCondition(
                self.measure(condition.measure, scope), condition.operator,
                v.VarValue(self.vars[value.name.text]) if isinstance(value, ast.Reference)
                else to_si(value))
        if condition.owner.text == "controller":
            return spec.ControllerFailedCondition()
        state = state_in_scope(scope, condition)
        if state is None and condition.field.text == "interpolated":
            return spec.InterpolatedCondition(condition.owner.text)
        if state is None:
            return spec.ReachedCondition(condition.owner.text)
        if condition.field.text == "done":
            return spec.DoneCondition(state)
        return spec.FinalCondition(state, condition.field.text,
                                   condition.region.text if condition.region else None)

    def measure(self, measure: ast.Measure, scope: tuple) -> spec.MeasureSpec:
        if isinstance(measure, ast.Elapsed):
            return spec.ElapsedMeasure()
        if isinstance(measure, ast.Time):
            return spec.TimeMeasure()
        if isinstance(measure, ast.Clearance):
            return spec.ClearanceMeasure(measure.first.text, measure.second.text)
        if isinstance(measure, ast.Distance):
            return spec.DistanceMeasure(measure.first.text, measure.second.text)
        if isinstance(measure, ast.Wrench):
            return v.wrench(measure)
        if isinstance(measure, ast.Variable):
            return v.VarValue(self.vars[measure.name.text])
        position = v.body_position(measure)
        if position is not None and measure.owner.text not in self.tasks:
            return position
        state = state_in_scope(scope, measure)
        if state is not None:
            return spec.VisitsMeasure(state)
        return spec.TaskMeasure(measure.owner.text, measure.field.text)


STATE_FIELDS = ("done", "visits")


def state_in_scope(scope: tuple, member: ast.Member) -> str | None:
    """The path of the state a member condition reads (``S.FINAL``, ``S.done``,
    ``S.REGION.FINAL``, ``S.visits``), or ``None`` when it reads a task."""
    for machine in scope:
        if member.owner.text in machine:
            path, decl = machine[member.owner.text]
            if member.region is not None or member.field.text in STATE_FIELDS \
                    or decl.regions:
                return path
            return None
    return None
