"""Print a mission syntax tree back as text.

Items and state parts keep their order; spacing and number spelling are normalised.
Parsing the output gives an equal tree, and formatting it again gives it back.
:func:`format_mission` prints a tree alone, in the canonical layout;
:func:`format_source` prints a tree with the text it was parsed from, keeping its
comments and the author's layout where it carries meaning (see :mod:`.layout`).
"""

from __future__ import annotations

import dataclasses
import math
from contextvars import ContextVar

from . import ast
from .layout import (BLANK, ROW_BREAK, Line, aligned, comments, joined, rows_split,
                     vector_separators, with_author_blanks, with_comments)

__all__ = ["comments", "format_mission", "format_source", "format_value", "item_lines"]

INDENT = "    "
_ONE_LINERS = (ast.WorldDecl, ast.ControllerDecl, ast.EventDecl, ast.StartDecl, ast.Import,
               ast.Let, ast.VarDecl)
_SOURCE: ContextVar[list[str] | None] = ContextVar("source", default=None)
"""The lines of the text :func:`format_source` prints (``None`` otherwise): a vector, a
call's arguments and a condition's ``and``/``or`` keep the rows they were written in."""


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
        return _vector(value)
    if isinstance(value, ast.Reference):
        return value.name.text
    if isinstance(value, ast.Offset):
        return f"{value.body.text} offset {format_value(value.offset)}"
    if isinstance(value, ast.Call):
        return f"{value.kind.text}({_arguments(value.arguments)})"
    return format_string(value.text)


def _vector(vector: ast.Vector) -> str:
    """``[a, b, c] unit``; while :func:`format_source` prints, with the author's rows
    and spaces between elements (:func:`~.layout.vector_separators`)."""
    elements = [_element(e) for e in vector.values]
    source = _SOURCE.get()
    span = vector.span
    separators = vector_separators(source, (span.line, span.column),
                                   (span.end_line, span.end_column)) \
        if source is not None and span.line > 0 else None
    if separators is None or len(separators) != len(elements) + 1:
        return "[" + ", ".join(elements) + "]" + _unit(vector.unit)
    return "[" + "".join(map(str.__add__, separators, elements)) + separators[-1] + "]" \
        + _unit(vector.unit)


def _element(element: float | ast.NameElement) -> str:
    if isinstance(element, ast.NameElement):
        return ("-" if element.negative else "") + element.name.text
    return format_number(element)


def _arguments(arguments: tuple[ast.Argument, ...]) -> str:
    return _joined([_argument(a) for a in arguments], arguments, ", ")


def _joined(texts: list[str], nodes, separator: str) -> str:
    """``texts`` joined by ``separator``; while :func:`format_source` prints, a row
    break after it where the author started the next node on a later line."""
    if _SOURCE.get() is None:
        return separator.join(texts)
    out = texts[:1]
    for text, previous, node in zip(texts[1:], nodes, nodes[1:]):
        broken = 0 < previous.span.end_line < node.span.line
        out.append((separator.rstrip() + ROW_BREAK if broken else separator) + text)
    return "".join(out)


def _argument(argument: ast.Argument) -> str:
    value = format_value(argument.value)
    return f"{argument.name.text} = {value}" if argument.name else value


_PRECEDENCE = {ast.Or: 1, ast.And: 2, ast.Not: 3}


def _operand(condition: ast.Condition, parent: int) -> str:
    text = format_condition(condition)
    own = _PRECEDENCE.get(type(condition), 4)
    return f"({text})" if own <= parent and own < 3 else text


_STRENGTH = {"+": 1, "-": 1, "*": 2, "/": 2}


def format_expression(node, parent: int = 0, right: bool = False) -> str:
    """An expression with the parentheses its structure needs and no others (a right
    operand of ``-`` or ``/`` keeps its own, a negated number too: ``-1`` is a number)."""
    if isinstance(node, ast.Binary):
        own = _STRENGTH[node.operator]
        text = (f"{format_expression(node.left, own)} {node.operator} "
                f"{format_expression(node.right, own, True)}")
        return f"({text})" if own < parent or (own == parent and right) else text
    if isinstance(node, ast.Negative):
        operand = format_expression(node.operand, 3)
        return f"-({operand})" if isinstance(node.operand, ast.Quantity) else "-" + operand
    if isinstance(node, (ast.Quantity, ast.Vector)):
        return format_value(node)
    if isinstance(node, ast.Variable):
        return node.name.text
    return format_measure(node)


def format_measure(measure: ast.Measure) -> str:
    if isinstance(measure, ast.Variable):
        return measure.name.text
    if isinstance(measure, ast.Wrench):
        axis = f".{measure.axis.text}" if measure.axis is not None else ""
        return f"{'torque' if measure.torque else 'force'}({measure.body.text}){axis}"
    if isinstance(measure, ast.Member):
        region = f"{measure.region.text}." if measure.region is not None else ""
        return f"{measure.owner.text}.{region}{measure.field.text}"
    if isinstance(measure, ast.Elapsed):
        return "elapsed"
    if isinstance(measure, ast.Time):
        return "time"
    word = "clearance" if isinstance(measure, ast.Clearance) else "distance"
    return f"{word}({measure.first.text}, {measure.second.text})"


def format_condition(condition: ast.Condition) -> str:
    """A condition with the parentheses its structure needs and no others."""
    if isinstance(condition, ast.Or):
        return _joined([_operand(c, 1) for c in condition.operands], condition.operands, " or ")
    if isinstance(condition, ast.And):
        return _joined([_operand(c, 2) for c in condition.operands], condition.operands,
                       " and ")
    if isinstance(condition, ast.Not):
        return "not " + _operand(condition.operand, 2)
    if isinstance(condition, ast.Comparison):
        return (f"{format_measure(condition.measure)} {condition.operator} "
                f"{format_value(condition.quantity)}")
    if isinstance(condition, ast.EventCondition):
        return f"event {condition.event.text}"
    if isinstance(condition, ast.Contact):
        return f"contact({condition.first.text}, {condition.second.text})"
    return format_measure(condition)


def format_action(action: ast.Action) -> str:
    if isinstance(action, (ast.Enable, ast.Disable, ast.Reset)):
        verb = type(action).__name__.lower()
        return f"{verb} {', '.join(n.text for n in action.names)}"
    if isinstance(action, ast.Assign):
        return f"{action.owner.text}.{action.field.text} = {format_value(action.value)}"
    if isinstance(action, ast.SetVar):
        return f"{action.name.text} = {format_expression(action.value)}"
    if isinstance(action, ast.Attach):
        return f"attach {action.body.text} to {action.parent.text}"
    if isinstance(action, ast.Detach):
        return f"detach {action.body.text}"
    if isinstance(action, ast.Emit):
        return f"emit {action.event.text}"
    return f"log {format_string(action.text)}"


def format_transition(transition: ast.Transition) -> str:
    return f"when {format_condition(transition.condition)} -> {transition.target.text}"


def _action_lines(actions: tuple[ast.Action, ...]) -> list[Line]:
    return [Line(format_action(a), a.span.line,
                 ("=",) if isinstance(a, (ast.Assign, ast.SetVar)) else ()) for a in actions]


def _transition_lines(transition: ast.Transition) -> list[Line]:
    header = format_transition(transition)
    if not transition.actions:
        return [Line(header, transition.span.line, ("->",))]
    return _block(header, transition.span, _action_lines(transition.actions), ("->",),
                  _one_line(transition))


def _one_line(node) -> bool:
    """Whether a block of one action was written on one line."""
    return len(node.actions) == 1 and node.span.line == node.span.end_line


def _block(header: str, span, lines: list[Line], anchors: tuple[str, ...] = (),
           joinable: bool = False) -> list[Line]:
    """``header {``, the indented ``lines`` and ``}``; ``span`` is the block's source."""
    if not lines:
        return [Line(f"{header} {{}}", span.line, anchors)]
    body = (dataclasses.replace(line, text=f"{INDENT}{line.text}") if line.text else line
            for line in lines)
    return [Line(f"{header} {{", span.line, anchors, joinable), *body,
            Line("}", span.end_line)]


def _part_lines(part: ast.StatePart) -> list[Line]:
    if isinstance(part, ast.ActionBlock):
        return _block(part.kind, part.span, _action_lines(part.actions), (), _one_line(part))
    return _transition_lines(part)


def _state_body(state: ast.StateDecl, inner: list[Line]) -> list[Line]:
    """The state's parts, with ``inner`` (its machine or regions) set apart by blank
    lines after the leading blocks, so that the parts keep their order."""
    if not inner:
        return [line for part in state.parts for line in _part_lines(part)]
    leading = next((i for i, p in enumerate(state.parts) if not isinstance(p, ast.ActionBlock)),
                   len(state.parts))
    sections = [[line for p in state.parts[:leading] for line in _part_lines(p)], inner,
                [line for p in state.parts[leading:] for line in _part_lines(p)]]
    return [line for section in _separated(sections) for line in section]


def _separated(sections: list[list[Line]]) -> list[list[Line]]:
    """The non-empty sections, each after the first preceded by a blank line."""
    kept = [section for section in sections if section]
    return kept[:1] + [[BLANK, *section] for section in kept[1:]]


def _region_lines(region: ast.Region) -> list[Line]:
    header = f"region {region.name.text}"
    if region.instance is not None:
        return [Line(f"{header}: {_instance(region.instance)}", region.span.line)]
    return _block(header, region.span, _machine_lines(region.machine))


def _instance(instance: ast.Instance) -> str:
    return f"{instance.behavior.text}({_arguments(instance.arguments)})"


def _state_lines(state: ast.StateDecl) -> list[Line]:
    if state.final:
        header = f"final {state.name.text}" + (f": {state.outcome.text}" if state.outcome else "")
        if not state.parts:
            return [Line(header, state.span.line)]
        return _block(header, state.span, _state_body(state, []))
    header = f"state {state.name.text}"
    if state.instance is not None:
        header += f": {_instance(state.instance)}"
        if not state.parts:
            return [Line(header, state.span.line)]
        return _block(header, state.span, _state_body(state, []))
    if state.parallel:
        regions = [line for region in state.regions for line in _region_lines(region)]
        return _block(f"{header}: parallel", state.span, _state_body(state, regions))
    inner = [line for region in state.regions for line in _machine_lines(region.machine)]
    return _block(header, state.span, _state_body(state, inner))


def _machine_lines(machine: ast.Machine) -> list[Line]:
    return _items_lines(machine.items)


def _declaration_lines(keyword: str, decl) -> list[Line]:
    arguments = ", ".join(a.text for a in decl.arguments)
    header = f"{keyword} {decl.name.text}: {decl.kind.text}({arguments})"
    if not decl.parameters:
        return [Line(header, decl.span.line)]
    width = max(len(p.name.text) for p in decl.parameters)
    lines = [Line(f"{p.name.text:<{width}} = {format_value(p.value)}", p.span.line)
             for p in decl.parameters]
    return _block(header, decl.span, lines)


def _behavior_lines(behavior: ast.BehaviorDecl) -> list[Line]:
    parameters = ", ".join(map(_behavior_param, behavior.parameters))
    header = f"behavior {behavior.name.text}({parameters})"
    return _block(header, behavior.span, _machine_lines(behavior.machine))


def _behavior_param(parameter: ast.BehaviorParam) -> str:
    text = f"{parameter.name.text}: {parameter.kind.text}"
    if parameter.default is not None:
        text += f" = {format_value(parameter.default)}"
    return text


def _described(keyword: str, name: ast.Name, description: str | None) -> str:
    described = f" {format_string(description)}" if description is not None else ""
    return f"{keyword} {name.text}{described}"


def _single(item: ast.Item) -> str | None:
    """The text of an item that always prints on one line, else ``None``."""
    if isinstance(item, ast.MissionHeader):
        return _described("mission", item.name, item.description)
    if isinstance(item, ast.LibraryHeader):
        return _described("library", item.name, item.description)
    if isinstance(item, ast.Import):
        return f"import {format_string(item.path.text)}"
    if isinstance(item, ast.Let):
        return f"let {item.name.text} = {format_value(item.value)}"
    if isinstance(item, ast.WorldDecl):
        return f"world {format_string(item.path.text)}"
    if isinstance(item, ast.ControllerDecl):
        return f"controller {item.name.text}"
    if isinstance(item, ast.EventDecl):
        return _described("event", item.name, item.description)
    if isinstance(item, ast.StartDecl):
        return f"start {item.state.text}"
    if isinstance(item, ast.VarDecl):
        value = f" = {format_expression(item.value)}" if item.value is not None else ""
        return f"var {item.name.text}: {item.kind.text}{value}"
    return None


def item_lines(item: ast.Item) -> list[Line]:
    """The lines of one item, each with the source line it prints."""
    text = _single(item)
    if text is not None:
        typed = (":",) if isinstance(item, ast.VarDecl) else ()
        valued = isinstance(item, ast.Let) or (isinstance(item, ast.VarDecl) and item.value)
        return [Line(text, item.span.line, typed + (("=",) if valued else ()))]
    if isinstance(item, ast.BehaviorDecl):
        return _behavior_lines(item)
    if isinstance(item, ast.TaskDecl):
        return _declaration_lines("task", item)
    if isinstance(item, ast.ConstraintDecl):
        return _declaration_lines("constraint", item)
    if isinstance(item, ast.StateDecl):
        return _state_lines(item)
    return _transition_lines(item)


def format_item(item: ast.Item) -> list[str]:
    """The lines of one top-level item."""
    return [line.text for line in item_lines(item)]


def _packed(previous: ast.Item, item: ast.Item) -> bool:
    """Whether two consecutive items sit on adjacent lines (no blank line between)."""
    if isinstance(previous, _ONE_LINERS) and isinstance(item, _ONE_LINERS):
        return True
    if isinstance(previous, ast.Transition) and isinstance(item, ast.Transition):
        return not previous.actions and not item.actions
    return (isinstance(previous, ast.StateDecl) and isinstance(item, ast.StateDecl)
            and previous.final and item.final and not previous.parts and not item.parts)


def _items_lines(items) -> list[Line]:
    """Items one after the other, with a blank line between unrelated ones."""
    lines: list[Line] = []
    previous = None
    for item in items:
        if previous is not None and not _packed(previous, item):
            lines.append(BLANK)
        lines += item_lines(item)
        previous = item
    return lines


def format_mission(mission: ast.Mission) -> str:
    """The whole mission as canonical text, ending with a newline."""
    return "\n".join(line.text for line in _items_lines(mission.items)) + "\n"


def format_source(mission: ast.Mission, text: str) -> str:
    """``mission`` printed with the comments and the author's layout of ``text``, the
    source it was parsed from; ending with a newline. The blank lines are the author's
    (the canonical ones between unrelated statements are not added)."""
    source = text.split("\n")
    written = _SOURCE.set(source)
    try:
        lines = [line for line in _items_lines(mission.items) if line is not BLANK]
    finally:
        _SOURCE.reset(written)
    lines = with_author_blanks(rows_split(aligned(joined(lines), source), source, INDENT),
                               source)
    return "\n".join(with_comments(lines, source, comments(text), INDENT)) + "\n"
