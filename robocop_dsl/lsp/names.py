"""Every name written in a mission file, with the role its place gives it.

A walk over the syntax tree lists each :class:`~robocop_dsl.lang.ast.Name` once, as a
declaration (``task arms: ...`` declares ``arms``) or a use whose role says what it may
name (``enable arms`` names a task or constraint). Navigation resolves uses to
declarations; semantic highlighting colours by role.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..lang import ast

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
# Uses.
CONTROLLED = "task or constraint"
OWNER = "owner"                  # before a dot: a task, constraint, state or `controller`
VALUE = "value"                  # a constant, a body, a behaviour parameter, world...
SUBJECT = "subject"              # what a task or constraint drives: a body or joint group
BODY = "body"
CONTROLLER = "controller"
TYPE = "type"                    # a task or constraint type
FIELD = "field"                  # after a dot
SETTING = "setting"              # a parameter name inside a declaration's block
CALL = "call"                    # an interpolator, feedback law or pose(...)
ARGUMENT = "argument"            # a named argument of a call or instance
KIND = "kind"                    # a behaviour parameter's type
OUTCOME = "outcome"              # `failure` after a final
UNIT = "unit"

DECLARATIONS = (TASK, CONSTRAINT, EVENT, BEHAVIOR, CONSTANT, STATE, FINAL, REGION, PARAM)


@dataclass(frozen=True)
class Occurrence:
    """One name as written. ``declares`` when it is the declared name itself;
    ``machines`` are the machines around it, innermost first (for state names);
    ``behavior`` the behaviour it is written in; ``context`` what the role needs to
    know (a declaration's type for :data:`SETTING`, a call's kind for
    :data:`ARGUMENT`, the owner for :data:`FIELD`)."""

    role: str
    name: ast.Name
    declares: bool = False
    machines: tuple = ()
    behavior: ast.BehaviorDecl | None = None
    context: str | None = None

    @property
    def text(self) -> str:
        return self.name.text

    def contains(self, line: int, column: int) -> bool:
        """Whether the 1-based position is on the name (its end included)."""
        span = self.name.span
        return span.line == line and span.column <= column <= span.end_column


class _Walker:
    def __init__(self):
        self.found: list[Occurrence] = []
        self.machines: tuple = ()
        self.behavior: ast.BehaviorDecl | None = None

    def add(self, role: str, name: ast.Name | None, declares: bool = False,
            context: str | None = None) -> None:
        if name is not None and name.span.line > 0:
            self.found.append(Occurrence(role, name, declares, self.machines, self.behavior,
                                         context))

    def mission(self, tree: ast.Mission) -> None:
        self.machines = (tree.machine,)
        for item in tree.items:
            self.item(item)

    def item(self, item) -> None:
        if isinstance(item, ast.Let):
            self.add(CONSTANT, item.name, True)
            self.value(item.value)
        elif isinstance(item, ast.ControllerDecl):
            self.add(CONTROLLER, item.name)
        elif isinstance(item, (ast.TaskDecl, ast.ConstraintDecl)):
            self.declaration(item)
        elif isinstance(item, ast.EventDecl):
            self.add(EVENT, item.name, True)
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
        self.add(family, decl.name, True)
        self.add(TYPE, decl.kind, context=family)
        for argument in decl.arguments:
            self.add(SUBJECT, argument, context=decl.kind.text)
        for parameter in decl.parameters:
            self.add(SETTING, parameter.name, context=f"{family}:{decl.kind.text}")
            self.value(parameter.value)

    def behavior_decl(self, behavior: ast.BehaviorDecl) -> None:
        self.add(BEHAVIOR, behavior.name, True)
        outer = self.machines, self.behavior
        self.behavior, self.machines = behavior, (behavior.machine,)
        for parameter in behavior.parameters:
            self.add(PARAM, parameter.name, True)
            self.add(KIND, parameter.kind)
            if parameter.default is not None:
                self.value(parameter.default)
        for item in behavior.machine.items:
            self.item(item)
        self.machines, self.behavior = outer

    def state(self, state: ast.StateDecl) -> None:
        self.add(FINAL if state.final else STATE, state.name, True)
        self.add(OUTCOME, state.outcome)
        if state.instance is not None:
            self.instance(state.instance)
        for part in state.parts:
            if isinstance(part, ast.ActionBlock):
                self.actions(part.actions)
            else:
                self.transition(part)
        for region in state.regions:
            self.add(REGION, region.name, True)
            if region.instance is not None:
                self.instance(region.instance)
            if region.machine is not None:
                outer = self.machines
                self.machines = (region.machine, *outer)
                for item in region.machine.items:
                    self.item(item)
                self.machines = outer

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
            self.condition(condition.measure)
            self.value(condition.quantity)
        elif isinstance(condition, ast.EventCondition):
            self.add(EVENT, condition.event)
        elif isinstance(condition, ast.Distance):
            self.add(BODY, condition.first)
            self.add(BODY, condition.second)
        elif isinstance(condition, ast.Member):
            self.add(OWNER, condition.owner)
            self.add(REGION, condition.region, context=condition.owner.text)
            self.add(FIELD, condition.field, context=condition.owner.text)

    def actions(self, actions) -> None:
        for action in actions:
            if isinstance(action, (ast.Enable, ast.Disable, ast.Reset)):
                for name in action.names:
                    self.add(CONTROLLED, name)
            elif isinstance(action, ast.Assign):
                self.add(CONTROLLED, action.owner)
                self.add(FIELD, action.field, context=action.owner.text)
                self.value(action.value)
            elif isinstance(action, ast.Attach):
                self.add(BODY, action.body)
                self.add(BODY, action.parent)
            elif isinstance(action, ast.Detach):
                self.add(BODY, action.body)
            elif isinstance(action, ast.Emit):
                self.add(EVENT, action.event)

    def value(self, value) -> None:
        if isinstance(value, ast.Quantity):
            self.add(UNIT, value.unit)
        elif isinstance(value, ast.Vector):
            for element in value.values:
                if isinstance(element, ast.NameElement):
                    self.add(VALUE, element.name)
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


def occurrences(tree: ast.Mission) -> list[Occurrence]:
    """Every name of ``tree`` in the order the walk meets them."""
    walker = _Walker()
    walker.mission(tree)
    return walker.found


def at(found: list[Occurrence], line: int, column: int) -> Occurrence | None:
    """The name at a 1-based position, if any."""
    return next((o for o in found if o.contains(line, column)), None)
