"""Every name written in a mission file, with the role its place gives it.

A walk over the syntax tree lists each :class:`~robocop_dsl.lang.ast.Name` once, as a
declaration (``task arms: ...`` declares ``arms``) or a use whose role says what it may
name (``enable arms`` names a task or constraint). Navigation resolves uses to
declarations; semantic highlighting colours by role.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from ..diagnostics import Span
from ..lang import ast
from ..lang.catalogue import AXES as AXES_KIND, CONSTRAINTS, TASKS

# Declarations.
TASK = "task"
CONSTRAINT = "constraint"
EVENT = "event"
BEHAVIOR = "behavior"
CONSTANT = "constant"
STATE = "state"
FINAL = "final"
REGION = "region"
PARAM = "parameter"              # a behaviour's parameter
VAR = "var"                      # a value that changes at run time
# Uses.
CONTROLLED = "task or constraint"
OWNER = "owner"                  # before a dot: a task, constraint, state or `controller`
VALUE = "value"                  # a constant, a body, a behaviour parameter, world...
SUBJECT = "subject"              # what a task or constraint drives: a body or joint group
BODY = "body"
SET = "body or joint group"      # a collision set: clearance(A, B), contact(A, B)
READ = "read"                    # a number read by name: a var, a constant, a parameter
ASSIGNED = "assigned"            # before `=` in an action: a var
CONTROLLER = "controller"
TYPE = "type"                    # a task or constraint type
FIELD = "field"                  # after a dot
SETTING = "setting"              # a parameter name inside a declaration's block
CALL = "call"                    # an interpolator, feedback law or pose(...)
ARGUMENT = "argument"            # a named argument of a call or instance
KIND = "kind"                    # a behaviour parameter's type or a var's kind
OUTCOME = "outcome"              # `failure` after a final
UNIT = "unit"

DECLARATIONS = (TASK, CONSTRAINT, EVENT, BEHAVIOR, CONSTANT, STATE, FINAL, REGION, PARAM,
                VAR)
AXES = ("x", "y", "z")
_STRING = re.compile(r'"([^"\\\n]|\\.)*"')
_PLACEHOLDER = re.compile(r"\{\s*([A-Za-z_][A-Za-z0-9_]*)\s*\}")


@dataclass(frozen=True, slots=True)
class Occurrence:
    """One name as written. ``declares`` when it is the declared name itself, ``node``
    then the declaration; ``machines`` are the machines around it, innermost first (for
    state and var names); ``behavior`` the behaviour it is written in; ``context`` what
    the role needs to know (a declaration's type for :data:`SETTING`, a call's kind for
    :data:`ARGUMENT`, the owner for :data:`FIELD`, the region a :data:`VAR` is declared
    in, the state a :data:`REGION` declared belongs to)."""

    role: str
    name: ast.Name
    declares: bool = False
    machines: tuple = ()
    behavior: ast.BehaviorDecl | None = None
    context: str | None = None
    node: object = field(default=None, compare=False)

    @property
    def text(self) -> str:
        return self.name.text

    def contains(self, line: int, column: int) -> bool:
        """Whether the 1-based position is on the name (its end included)."""
        span = self.name.span
        return span.line == line and span.column <= column <= span.end_column


class _Walker:
    def __init__(self, text: str):
        self.lines = text.split("\n")
        self.found: list[Occurrence] = []
        self.machines: tuple = ()
        self.behavior: ast.BehaviorDecl | None = None
        self.region: str | None = None

    def add(self, role: str, name: ast.Name | None, declares: bool = False,
            context: str | None = None, node=None) -> None:
        if name is not None and name.span.line > 0:
            self.found.append(Occurrence(role, name, declares, self.machines, self.behavior,
                                         context, node))

    def mission(self, tree: ast.Mission) -> None:
        self.machines = (tree.machine,)
        for item in tree.items:
            self.item(item)

    def item(self, item) -> None:
        if isinstance(item, ast.Let):
            self.add(CONSTANT, item.name, True, node=item)
            self.value(item.value)
        elif isinstance(item, ast.VarDecl):
            self.add(VAR, item.name, True, self.region, item)
            self.add(KIND, item.kind, context=VAR)
            if item.value is not None:
                self.expression(item.value)
        elif isinstance(item, ast.ControllerDecl):
            self.add(CONTROLLER, item.name)
        elif isinstance(item, (ast.TaskDecl, ast.ConstraintDecl)):
            self.declaration(item)
        elif isinstance(item, ast.EventDecl):
            self.add(EVENT, item.name, True, node=item)
        elif isinstance(item, ast.BehaviorDecl):
            self.behavior_decl(item)
        elif isinstance(item, ast.StartDecl):
            self.add(STATE, item.state)
        elif isinstance(item, ast.StateDecl):
            self.state(item)
        elif isinstance(item, ast.Transition):
            self.transition(item)

    def declaration(self, decl) -> None:
        family = TASK if isinstance(decl, ast.TaskDecl) else CONSTRAINT
        self.add(family, decl.name, True, node=decl)
        self.add(TYPE, decl.kind, context=family)
        for argument in decl.arguments:
            self.add(SUBJECT, argument, context=decl.kind.text)
        kind = (TASKS if family == TASK else CONSTRAINTS).get(decl.kind.text)
        for parameter in decl.parameters:
            self.add(SETTING, parameter.name, context=f"{family}:{decl.kind.text}")
            spec = kind.parameter(parameter.name.text) if kind is not None else None
            if spec is not None and spec.kind == AXES_KIND \
                    and isinstance(parameter.value, ast.Vector):
                for element in parameter.value.values:
                    if isinstance(element, ast.NameElement):
                        self.add(FIELD, element.name, context=AXES_KIND)
            else:
                self.value(parameter.value)

    def behavior_decl(self, behavior: ast.BehaviorDecl) -> None:
        self.add(BEHAVIOR, behavior.name, True, node=behavior)
        outer = self.machines, self.behavior, self.region
        self.behavior, self.machines, self.region = behavior, (behavior.machine,), None
        for parameter in behavior.parameters:
            self.add(PARAM, parameter.name, True)
            self.add(KIND, parameter.kind)
            if parameter.default is not None:
                self.value(parameter.default)
        for item in behavior.machine.items:
            self.item(item)
        self.machines, self.behavior, self.region = outer

    def state(self, state: ast.StateDecl) -> None:
        self.add(FINAL if state.final else STATE, state.name, True, node=state)
        self.add(OUTCOME, state.outcome)
        if state.instance is not None:
            self.instance(state.instance)
        for part in state.parts:
            if isinstance(part, ast.ActionBlock):
                self.actions(part.actions)
            else:
                self.transition(part)
        for region in state.regions:
            self.add(REGION, region.name, True, state.name.text, region)
            if region.instance is not None:
                self.instance(region.instance)
            if region.machine is not None:
                outer = self.machines, self.region
                self.machines = (region.machine, *outer[0])
                if region.name is not None:
                    self.region = f"{state.name.text}.{region.name.text}"
                for item in region.machine.items:
                    self.item(item)
                self.machines, self.region = outer

    def instance(self, instance: ast.Instance) -> None:
        self.add(BEHAVIOR, instance.behavior)
        for argument in instance.arguments:
            self.add(ARGUMENT, argument.name, context=instance.behavior.text)
            self.value(argument.value)

    def transition(self, transition: ast.Transition) -> None:
        self.condition(transition.condition)
        self.add(STATE, transition.target)
        self.actions(transition.actions)

    def condition(self, condition) -> None:
        if isinstance(condition, (ast.And, ast.Or)):
            for operand in condition.operands:
                self.condition(operand)
        elif isinstance(condition, ast.Not):
            self.condition(condition.operand)
        elif isinstance(condition, ast.Comparison):
            self.expression(condition.measure)
            if isinstance(condition.quantity, ast.Reference):
                self.add(READ, condition.quantity.name)
            else:
                self.value(condition.quantity)
        elif isinstance(condition, ast.EventCondition):
            self.add(EVENT, condition.event)
        elif isinstance(condition, ast.Contact):
            self.add(SET, condition.first)
            self.add(SET, condition.second)
        else:
            self.expression(condition)

    def expression(self, node) -> None:
        """A measure, or an expression over numbers, vars, constants and measures."""
        if isinstance(node, ast.Binary):
            self.expression(node.left)
            self.expression(node.right)
        elif isinstance(node, ast.Negative):
            self.expression(node.operand)
        elif isinstance(node, ast.Variable):
            self.add(READ, node.name)
        elif isinstance(node, ast.Wrench):
            self.add(BODY, node.body)
            self.add(FIELD, node.axis, context="torque" if node.torque else "force")
        elif isinstance(node, ast.Distance):
            role = SET if isinstance(node, ast.Clearance) else BODY
            self.add(role, node.first)
            self.add(role, node.second)
        elif isinstance(node, ast.Member):
            self.member(node)
        else:
            self.value(node)

    def member(self, member: ast.Member) -> None:
        """``owner.field``, ``state.region.final`` or ``body.position.x``."""
        self.add(OWNER, member.owner)
        if member.region is not None and member.region.text == "position" \
                and member.field.text in AXES:
            self.add(FIELD, member.region, context=member.owner.text)
            self.add(FIELD, member.field, context="position")
            return
        self.add(REGION, member.region, context=member.owner.text)
        self.add(FIELD, member.field, context=member.owner.text)

    def actions(self, actions) -> None:
        for action in actions:
            if isinstance(action, (ast.Enable, ast.Disable, ast.Reset)):
                for name in action.names:
                    self.add(CONTROLLED, name)
            elif isinstance(action, ast.Assign):
                self.add(CONTROLLED, action.owner)
                self.add(FIELD, action.field, context=action.owner.text)
                self.value(action.value)
            elif isinstance(action, ast.SetVar):
                self.add(ASSIGNED, action.name)
                self.expression(action.value)
            elif isinstance(action, ast.Attach):
                self.add(BODY, action.body)
                self.add(BODY, action.parent)
            elif isinstance(action, ast.Detach):
                self.add(BODY, action.body)
            elif isinstance(action, ast.Emit):
                self.add(EVENT, action.event)
            elif isinstance(action, ast.Log):
                for name in self.placeholders(action):
                    self.add(READ, name)

    def placeholders(self, log: ast.Log) -> list[ast.Name]:
        """The ``{NAME}`` of a log text, each at its place in the file."""
        line = log.span.line
        text = self.lines[line - 1] if 0 < line <= len(self.lines) else ""
        string = _STRING.search(text, log.span.column - 1)
        if string is None:
            return []
        return [ast.Name(m.group(1), span=Span(line, m.start(1) + 1, line, m.end(1) + 1))
                for m in _PLACEHOLDER.finditer(text, string.start(), string.end())]

    def value(self, value) -> None:
        if isinstance(value, ast.Quantity):
            self.add(UNIT, value.unit)
        elif isinstance(value, ast.Vector):
            for element in value.values:
                if isinstance(element, ast.NameElement):
                    self.add(READ, element.name)
            self.add(UNIT, value.unit)
        elif isinstance(value, ast.Reference):
            self.add(VALUE, value.name)
        elif isinstance(value, ast.Offset):
            self.add(VALUE, value.body)
            self.value(value.offset)
        elif isinstance(value, ast.Call):
            self.add(CALL, value.kind)
            for argument in value.arguments:
                self.add(ARGUMENT, argument.name, context=value.kind.text)
                self.value(argument.value)


def occurrences(tree: ast.Mission, text: str = "") -> list[Occurrence]:
    """Every name of ``tree`` in the order the walk meets them; ``text``, the source
    of ``tree``, places the names written inside log texts."""
    walker = _Walker(text)
    walker.mission(tree)
    return walker.found


def at(found: list[Occurrence], line: int, column: int) -> Occurrence | None:
    """The name at a 1-based position, if any."""
    return next((o for o in found if o.contains(line, column)), None)


class Scopes:
    """Where states and vars are declared, to look a name up at once: by machine (the
    machines of the occurrences, by identity), the states declared anywhere in each
    behaviour or in the mission, and the vars of the top of the file."""

    def __init__(self, found: list[Occurrence]):
        self.states: dict[int, dict[str, Occurrence]] = {}
        self.variables: dict[int, dict[str, Occurrence]] = {}
        self.anywhere: dict[tuple[int, str], Occurrence] = {}
        self.top: dict[str, Occurrence] = {}
        for occurrence in found:
            if not occurrence.declares:
                continue
            machine = id(occurrence.machines[0]) if occurrence.machines else 0
            if occurrence.role in (STATE, FINAL):
                self.states.setdefault(machine, {}).setdefault(occurrence.text, occurrence)
                self.anywhere.setdefault((id(occurrence.behavior), occurrence.text),
                                         occurrence)
            elif occurrence.role == VAR:
                self.variables.setdefault(machine, {}).setdefault(occurrence.text, occurrence)
                if occurrence.behavior is None and len(occurrence.machines) == 1:
                    self.top.setdefault(occurrence.text, occurrence)

    def state(self, occurrence: Occurrence, name: str) -> Occurrence | None:
        """The state ``name`` seen from ``occurrence``: in the innermost machine around
        it that has one, else anywhere in the same behaviour or mission."""
        for machine in occurrence.machines:
            found = self.states.get(id(machine), {}).get(name)
            if found is not None:
                return found
        return self.anywhere.get((id(occurrence.behavior), name))

    def variable(self, occurrence: Occurrence, name: str) -> Occurrence | None:
        """The var ``name`` seen from ``occurrence``: declared in a machine around it,
        innermost first, else at the top of the file (every behaviour sees those)."""
        for machine in occurrence.machines:
            found = self.variables.get(id(machine), {}).get(name)
            if found is not None:
                return found
        return self.top.get(name)
