"""Print a mission syntax tree back as canonical text.

Items and state parts keep their order; layout, spacing and number spelling are
normalised and comments are not kept. Parsing the output gives an equal tree.
"""

from __future__ import annotations

import math

from . import ast

INDENT = "    "
_ONE_LINERS = (ast.WorldDecl, ast.ControllerDecl, ast.EventDecl, ast.StartDecl, ast.Import,
               ast.Let)


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
        return "[" + ", ".join(map(_element, value.values)) + "]" + _unit(value.unit)
    if isinstance(value, ast.Reference):
        return value.name.text
    if isinstance(value, ast.Offset):
        return f"{value.body.text} offset {format_value(value.offset)}"
    if isinstance(value, ast.Call):
        return f"{value.kind.text}({_arguments(value.arguments)})"
    return format_string(value.text)


def _element(element: float | ast.NameElement) -> str:
    if isinstance(element, ast.NameElement):
        return ("-" if element.negative else "") + element.name.text
    return format_number(element)


def _arguments(arguments: tuple[ast.Argument, ...]) -> str:
    return ", ".join(map(_argument, arguments))


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
        region = f"{measure.region.text}." if measure.region is not None else ""
        return f"{measure.owner.text}.{region}{measure.field.text}"
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


def _transition_lines(transition: ast.Transition) -> list[str]:
    header = format_transition(transition)
    if not transition.actions:
        return [header]
    return _block(header, [format_action(a) for a in transition.actions], 0)


def _block(header: str, lines: list[str], depth: int) -> list[str]:
    pad = INDENT * depth
    if not lines:
        return [f"{pad}{header} {{}}"]
    body = (f"{pad}{INDENT}{line}" if line else "" for line in lines)
    return [f"{pad}{header} {{", *body, f"{pad}}}"]


def _part_lines(part: ast.StatePart) -> list[str]:
    if isinstance(part, ast.ActionBlock):
        return _block(part.kind, [format_action(a) for a in part.actions], 0)
    return _transition_lines(part)


def _state_body(state: ast.StateDecl, inner: list[str]) -> list[str]:
    """The state's parts, with ``inner`` (its machine or regions) set apart by blank
    lines after the leading blocks, so that the parts keep their order."""
    if not inner:
        return [line for part in state.parts for line in _part_lines(part)]
    leading = next((i for i, p in enumerate(state.parts) if not isinstance(p, ast.ActionBlock)),
                   len(state.parts))
    sections = [[line for p in state.parts[:leading] for line in _part_lines(p)], inner,
                [line for p in state.parts[leading:] for line in _part_lines(p)]]
    return [line for section in _separated(sections) for line in section]


def _separated(sections: list[list[str]]) -> list[list[str]]:
    """The non-empty sections, each after the first preceded by a blank line."""
    kept = [section for section in sections if section]
    return kept[:1] + [["", *section] for section in kept[1:]]


def _region_lines(region: ast.Region) -> list[str]:
    header = f"region {region.name.text}"
    if region.instance is not None:
        return [f"{header}: {_instance(region.instance)}"]
    return _block(header, _machine_lines(region.machine), 0)


def _instance(instance: ast.Instance) -> str:
    return f"{instance.behavior.text}({_arguments(instance.arguments)})"


def _state_lines(state: ast.StateDecl) -> list[str]:
    if state.final:
        header = f"final {state.name.text}" + (f": {state.outcome.text}" if state.outcome else "")
        return _block(header, _state_body(state, []), 0) if state.parts else [header]
    header = f"state {state.name.text}"
    if state.instance is not None:
        header += f": {_instance(state.instance)}"
        return _block(header, _state_body(state, []), 0) if state.parts else [header]
    if state.parallel:
        regions = [line for region in state.regions for line in _region_lines(region)]
        return _block(f"{header}: parallel", _state_body(state, regions), 0)
    inner = [line for region in state.regions for line in _machine_lines(region.machine)]
    return _block(header, _state_body(state, inner), 0)


def _machine_lines(machine: ast.Machine) -> list[str]:
    return _items_lines(machine.items)


def _declaration_lines(keyword: str, decl) -> list[str]:
    arguments = ", ".join(a.text for a in decl.arguments)
    header = f"{keyword} {decl.name.text}: {decl.kind.text}({arguments})"
    if not decl.parameters:
        return [header]
    width = max(len(p.name.text) for p in decl.parameters)
    lines = [f"{p.name.text:<{width}} = {format_value(p.value)}" for p in decl.parameters]
    return _block(header, lines, 0)


def _behavior_lines(behavior: ast.BehaviorDecl) -> list[str]:
    parameters = ", ".join(map(_behavior_param, behavior.parameters))
    header = f"behavior {behavior.name.text}({parameters})"
    return _block(header, _machine_lines(behavior.machine), 0)


def _behavior_param(parameter: ast.BehaviorParam) -> str:
    text = f"{parameter.name.text}: {parameter.kind.text}"
    if parameter.default is not None:
        text += f" = {format_value(parameter.default)}"
    return text


def _described(keyword: str, name: ast.Name, description: str | None) -> str:
    described = f" {format_string(description)}" if description is not None else ""
    return f"{keyword} {name.text}{described}"


def format_item(item: ast.Item) -> list[str]:
    """The lines of one top-level item."""
    if isinstance(item, ast.MissionHeader):
        return [_described("mission", item.name, item.description)]
    if isinstance(item, ast.LibraryHeader):
        return [_described("library", item.name, item.description)]
    if isinstance(item, ast.Import):
        return [f"import {format_string(item.path.text)}"]
    if isinstance(item, ast.Let):
        return [f"let {item.name.text} = {format_value(item.value)}"]
    if isinstance(item, ast.BehaviorDecl):
        return _behavior_lines(item)
    if isinstance(item, ast.WorldDecl):
        return [f"world {format_string(item.path.text)}"]
    if isinstance(item, ast.ControllerDecl):
        return [f"controller {item.name.text}"]
    if isinstance(item, ast.TaskDecl):
        return _declaration_lines("task", item)
    if isinstance(item, ast.ConstraintDecl):
        return _declaration_lines("constraint", item)
    if isinstance(item, ast.EventDecl):
        return [_described("event", item.name, item.description)]
    if isinstance(item, ast.StartDecl):
        return [f"start {item.state.text}"]
    if isinstance(item, ast.StateDecl):
        return _state_lines(item)
    return _transition_lines(item)


def _packed(previous: ast.Item, item: ast.Item) -> bool:
    """Whether two consecutive items sit on adjacent lines (no blank line between)."""
    if isinstance(previous, _ONE_LINERS) and isinstance(item, _ONE_LINERS):
        return True
    if isinstance(previous, ast.Transition) and isinstance(item, ast.Transition):
        return not previous.actions and not item.actions
    return (isinstance(previous, ast.StateDecl) and isinstance(item, ast.StateDecl)
            and previous.final and item.final and not previous.parts and not item.parts)


def _items_lines(items) -> list[str]:
    """Items one after the other, with a blank line between unrelated ones."""
    lines: list[str] = []
    previous = None
    for item in items:
        if previous is not None and not _packed(previous, item):
            lines.append("")
        lines += format_item(item)
        previous = item
    return lines


def format_mission(mission: ast.Mission) -> str:
    """The whole mission as canonical text, ending with a newline."""
    return "\n".join(_items_lines(mission.items)) + "\n"
