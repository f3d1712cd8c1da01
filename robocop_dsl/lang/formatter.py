"""Print a mission syntax tree back as canonical text.

Items and state parts keep their order; layout, spacing and number spelling are
normalised and comments are not kept. Parsing the output gives an equal tree.
"""

from __future__ import annotations

import math

from . import ast

INDENT = "    "
_ONE_LINERS = (ast.WorldDecl, ast.ControllerDecl, ast.EventDecl, ast.StartDecl)


def format_number(value: float) -> str:
    """Shortest text that reads back as ``value``: ``1``, ``0.25``, ``1e-06``."""
    if math.isinf(value):
        return "1e999" if value > 0 else "-1e999"
    if value.is_integer() and abs(value) < 1e16:
        return str(int(value))
    return repr(value)


def format_string(text: str) -> str:
    escaped = text.replace("\\", "\\\\").replace('"', '\\"')
    return '"' + escaped.replace("\n", "\\n").replace("\t", "\\t") + '"'


def _unit(unit: ast.Name | None) -> str:
    return f" {unit.text}" if unit is not None else ""


def format_value(value: ast.Value) -> str:
    """A parameter or target value as text."""
    if isinstance(value, ast.Quantity):
        return format_number(value.value) + _unit(value.unit)
    if isinstance(value, ast.Vector):
        return "[" + ", ".join(map(format_number, value.values)) + "]" + _unit(value.unit)
    if isinstance(value, ast.Reference):
        return value.name.text
    if isinstance(value, ast.Offset):
        return f"{value.body.text} offset {format_value(value.offset)}"
    if isinstance(value, ast.Call):
        return f"{value.kind.text}({', '.join(map(_argument, value.arguments))})"
    return format_string(value.text)


def _argument(argument: ast.Argument) -> str:
    value = format_value(argument.value)
    return f"{argument.name.text} = {value}" if argument.name else value


_PRECEDENCE = {ast.Or: 1, ast.And: 2, ast.Not: 3}


def _operand(condition: ast.Condition, parent: int) -> str:
    text = format_condition(condition)
    own = _PRECEDENCE.get(type(condition), 4)
    return f"({text})" if own <= parent and own < 3 else text


def format_measure(measure: ast.Measure) -> str:
    if isinstance(measure, ast.Member):
        return f"{measure.owner.text}.{measure.field.text}"
    if isinstance(measure, ast.Elapsed):
        return "elapsed"
    if isinstance(measure, ast.Time):
        return "time"
    return f"distance({measure.first.text}, {measure.second.text})"


def format_condition(condition: ast.Condition) -> str:
    """A condition with the parentheses its structure needs and no others."""
    if isinstance(condition, ast.Or):
        return " or ".join(_operand(c, 1) for c in condition.operands)
    if isinstance(condition, ast.And):
        return " and ".join(_operand(c, 2) for c in condition.operands)
    if isinstance(condition, ast.Not):
        return "not " + _operand(condition.operand, 2)
    if isinstance(condition, ast.Comparison):
        return (f"{format_measure(condition.measure)} {condition.operator} "
                f"{format_value(condition.quantity)}")
    if isinstance(condition, ast.EventCondition):
        return f"event {condition.event.text}"
    return format_measure(condition)


def format_action(action: ast.Action) -> str:
    if isinstance(action, (ast.Enable, ast.Disable, ast.Reset)):
        verb = type(action).__name__.lower()
        return f"{verb} {', '.join(n.text for n in action.names)}"
    if isinstance(action, ast.Assign):
        return f"{action.owner.text}.{action.field.text} = {format_value(action.value)}"
    if isinstance(action, ast.Attach):
        return f"attach {action.body.text} to {action.parent.text}"
    if isinstance(action, ast.Detach):
        return f"detach {action.body.text}"
    if isinstance(action, ast.Emit):
        return f"emit {action.event.text}"
    return f"log {format_string(action.text)}"


def format_transition(transition: ast.Transition) -> str:
    return f"when {format_condition(transition.condition)} -> {transition.target.text}"


def _block(header: str, lines: list[str], depth: int) -> list[str]:
    pad = INDENT * depth
    if not lines:
        return [f"{pad}{header} {{}}"]
    return [f"{pad}{header} {{", *(f"{pad}{INDENT}{line}" for line in lines), f"{pad}}}"]


def _state_lines(state: ast.StateDecl) -> list[str]:
    body: list[str] = []
    for part in state.parts:
        if isinstance(part, ast.ActionBlock):
            body += _block(part.kind, [format_action(a) for a in part.actions], 0)
        else:
            body.append(format_transition(part))
    if state.final:
        header = f"final {state.name.text}" + (f": {state.outcome.text}" if state.outcome else "")
        return _block(header, body, 0) if state.parts else [header]
    return _block(f"state {state.name.text}", body, 0)


def _declaration_lines(keyword: str, decl) -> list[str]:
    arguments = ", ".join(a.text for a in decl.arguments)
    header = f"{keyword} {decl.name.text}: {decl.kind.text}({arguments})"
    if not decl.parameters:
        return [header]
    width = max(len(p.name.text) for p in decl.parameters)
    lines = [f"{p.name.text:<{width}} = {format_value(p.value)}" for p in decl.parameters]
    return _block(header, lines, 0)


def format_item(item: ast.Item) -> list[str]:
    """The lines of one top-level item."""
    if isinstance(item, ast.MissionHeader):
        described = f" {format_string(item.description)}" if item.description is not None else ""
        return [f"mission {item.name.text}{described}"]
    if isinstance(item, ast.WorldDecl):
        return [f"world {format_string(item.path.text)}"]
    if isinstance(item, ast.ControllerDecl):
        return [f"controller {item.name.text}"]
    if isinstance(item, ast.TaskDecl):
        return _declaration_lines("task", item)
    if isinstance(item, ast.ConstraintDecl):
        return _declaration_lines("constraint", item)
    if isinstance(item, ast.EventDecl):
        described = f" {format_string(item.description)}" if item.description is not None else ""
        return [f"event {item.name.text}{described}"]
    if isinstance(item, ast.StartDecl):
        return [f"start {item.state.text}"]
    if isinstance(item, ast.StateDecl):
        return _state_lines(item)
    return [format_transition(item)]


def _packed(previous: ast.Item, item: ast.Item) -> bool:
    """Whether two consecutive items sit on adjacent lines (no blank line between)."""
    if isinstance(previous, _ONE_LINERS) and isinstance(item, _ONE_LINERS):
        return True
    if isinstance(previous, ast.Transition) and isinstance(item, ast.Transition):
        return True
    return (isinstance(previous, ast.StateDecl) and isinstance(item, ast.StateDecl)
            and previous.final and item.final and not previous.parts and not item.parts)


def format_mission(mission: ast.Mission) -> str:
    """The whole mission as canonical text, ending with a newline."""
    lines: list[str] = []
    previous = None
    for item in mission.items:
        if previous is not None and not _packed(previous, item):
            lines.append("")
        lines += format_item(item)
        previous = item
    return "\n".join(lines) + "\n"
