"""Build the syntax tree from lark's parse tree. Only building: checks come later."""

from __future__ import annotations

import functools
import sys

from lark import Token, Tree
from lark.exceptions import VisitError

from ..diagnostics import Span
from . import ast
from .ast import NO_SPAN


@functools.lru_cache(maxsize=1 << 12)
def _shared(number: int) -> int:
    """``number``, one object for each value met lately: the spans of a large mission
    repeat their line numbers, each an object of its own until shared (a sixth of the
    tree's memory)."""
    return number


def token_span(token: Token) -> Span:
    return Span(_shared(token.line), _shared(token.column), _shared(token.end_line),
                _shared(token.end_column))


def _code_end(line: str) -> int:
    """Length of ``line`` without a trailing comment and trailing blanks."""
    if "#" not in line:
        return len(line.rstrip())
    quoted = False
    for index, char in enumerate(line):
        if char == '"' and (index == 0 or line[index - 1] != "\\"):
            quoted = not quoted
        elif char == "#" and not quoted:
            return len(line[:index].rstrip())
    return len(line.rstrip())


def trimmed_span(text: str, meta) -> Span:
    """The span of a rule without the line breaks, blank lines and comments that end it."""
    if getattr(meta, "empty", True):
        return NO_SPAN
    end = meta.end_pos
    while True:
        line_start = text.rfind("\n", meta.start_pos, end) + 1 or meta.start_pos
        line_start = max(line_start, meta.start_pos)
        code = _code_end(text[line_start:end])
        if code or line_start == meta.start_pos:
            end = line_start + code
            break
        end = line_start - 1
    end_line = meta.line + text.count("\n", meta.start_pos, end)
    end_column = end - (text.rfind("\n", 0, end) + 1) + 1
    return Span(_shared(meta.line), _shared(meta.column), _shared(end_line),
                _shared(end_column))


def _name(token: Token) -> ast.Name:
    """A name; its text is interned: a mission repeats its names many times."""
    return ast.Name(sys.intern(str(token)), span=token_span(token))


def _number(token: Token) -> float:
    return float(token)


_ESCAPES = {"n": "\n", "t": "\t"}


def _string(token: Token) -> str:
    """The text of a STRING token without quotes; ``\\n`` and ``\\t`` are escapes,
    any other backslash keeps the character after it."""
    text, out, index = str(token)[1:-1], [], 0
    while index < len(text):
        char = text[index]
        if char == "\\" and index + 1 < len(text):
            index += 1
            char = _ESCAPES.get(text[index], text[index])
        out.append(char)
        index += 1
    return "".join(out)


def _tokens(children, kind: str) -> list[Token]:
    return [c for c in children if isinstance(c, Token) and c.type == kind]


def _nodes(children, kind) -> tuple:
    return tuple(c for c in children if isinstance(c, kind))


def _description(children) -> str | None:
    """The optional description string of a header or declaration."""
    strings = _tokens(children, "STRING")
    return _string(strings[0]) if strings else None


_PARTS = (ast.ActionBlock, ast.Transition)


def _inline_region(items: tuple) -> ast.Region:
    """The unnamed region of a compound state, spanning its nested items."""
    first, last = items[0].span, items[-1].span
    span = Span(first.line, first.column, last.end_line, last.end_column)
    return ast.Region(None, machine=ast.Machine(items, span=span), span=span)


class MissionBuilder:
    """Turn a lark tree of ``mission.lark`` for ``text`` into :class:`ast.Mission`: each
    rule's method gets the rule's positions (lark's ``meta``) and its children, built
    first; a rule without one stays a lark tree. An exception raised by a method comes
    out as lark's :class:`~lark.exceptions.VisitError`, as from a lark transformer."""

    def __init__(self, text: str):
        self._text = text

    def transform(self, tree: Tree):
        """The syntax tree built from ``tree``."""
        children = [self.transform(c) if isinstance(c, Tree) else c for c in tree.children]
        build = getattr(self, tree.data, None)
        if build is None:
            return Tree(tree.data, children, tree.meta)
        try:
            return build(tree.meta, children)
        except Exception as error:
            raise VisitError(tree.data, tree, error) from error

    def _span(self, meta) -> Span:
        return trimmed_span(self._text, meta)

    def start(self, meta, children):
        return ast.Mission(tuple(children), span=self._span(meta))

    # ---- declarations ----
    def mission_header(self, meta, children):
        return ast.MissionHeader(_name(children[0]), _description(children),
                                 span=self._span(meta))

    def library_header(self, meta, children):
        return ast.LibraryHeader(_name(children[0]), _description(children),
                                 span=self._span(meta))

    def import_decl(self, meta, children):
        return ast.Import(ast.String(_string(children[0]), span=token_span(children[0])),
                          span=self._span(meta))

    def let_decl(self, meta, children):
        return ast.Let(_name(children[0]), children[1], span=self._span(meta))

    def world_decl(self, meta, children):
        return ast.WorldDecl(ast.String(_string(children[0]), span=token_span(children[0])),
                             span=self._span(meta))

    def controller_decl(self, meta, children):
        return ast.ControllerDecl(_name(children[0]), span=self._span(meta))

    def _declaration(self, node_type, meta, children):
        names = _tokens(children, "NAME")
        arguments = next((c for c in children if isinstance(c, tuple)), ())
        parameters = next((c for c in children if isinstance(c, list)), [])
        return node_type(_name(names[0]), _name(names[1]), arguments, tuple(parameters),
                         span=self._span(meta))

    def task_decl(self, meta, children):
        return self._declaration(ast.TaskDecl, meta, children)

    def constraint_decl(self, meta, children):
        return self._declaration(ast.ConstraintDecl, meta, children)

    def event_decl(self, meta, children):
        return ast.EventDecl(_name(children[0]), _description(children), span=self._span(meta))

    def name_list(self, meta, children):
        return tuple(_name(c) for c in children)

    def param_block(self, meta, children):
        return list(children)

    def param(self, meta, children):
        return ast.Parameter(_name(children[0]), children[1], span=self._span(meta))

    # ---- behaviours ----
    def behavior_decl(self, meta, children):
        return ast.BehaviorDecl(_name(children[0]), _nodes(children, ast.BehaviorParam),
                                children[-1], span=self._span(meta))

    def behavior_param(self, meta, children):
        default = children[2] if len(children) > 2 else None
        return ast.BehaviorParam(_name(children[0]), children[1], default,
                                 span=self._span(meta))

    def param_kind(self, meta, children):
        return _name(children[0])

    # ---- machines and states ----
    def machine_body(self, meta, children):
        return ast.Machine(tuple(children), span=self._span(meta))

    def start_decl(self, meta, children):
        return ast.StartDecl(_name(children[0]), span=self._span(meta))

    def state_decl(self, meta, children):
        body = children[1]
        nested = tuple(c for c in body if not isinstance(c, _PARTS))
        regions = (_inline_region(nested),) if nested else ()
        return ast.StateDecl(_name(children[0]), _nodes(body, _PARTS), regions=regions,
                             span=self._span(meta))

    def instance_state(self, meta, children):
        parts = children[2] if len(children) > 2 else []
        return ast.StateDecl(_name(children[0]), tuple(parts), instance=children[1],
                             span=self._span(meta))

    def parallel_state(self, meta, children):
        body = children[1]
        return ast.StateDecl(_name(children[0]), _nodes(body, _PARTS), parallel=True,
                             regions=_nodes(body, ast.Region), span=self._span(meta))

    def final_decl(self, meta, children):
        names = _tokens(children, "NAME")
        parts = next((c for c in children if isinstance(c, list)), [])
        outcome = _name(names[1]) if len(names) > 1 else None
        return ast.StateDecl(_name(names[0]), tuple(parts), final=True, outcome=outcome,
                             span=self._span(meta))

    def transition(self, meta, children):
        actions = children[2] if len(children) > 2 else ()
        return ast.Transition(children[0], _name(children[1]), actions, span=self._span(meta))

    def instance(self, meta, children):
        return ast.Instance(_name(children[0]), _nodes(children[1:], ast.Argument),
                            span=self._span(meta))

    def region(self, meta, children):
        body = children[1]
        if isinstance(body, ast.Instance):
            return ast.Region(_name(children[0]), instance=body, span=self._span(meta))
        return ast.Region(_name(children[0]), machine=body, span=self._span(meta))

    def state_body(self, meta, children):
        return list(children)

    def parallel_body(self, meta, children):
        return list(children)

    def part_body(self, meta, children):
        return list(children)

    def block_kind(self, meta, children):
        return str(children[0])

    def action_block(self, meta, children):
        return ast.ActionBlock(children[0], children[1], span=self._span(meta))

    def actions(self, meta, children):
        return tuple(children)

    # ---- actions ----
    def enable(self, meta, children):
        return ast.Enable(children[0], span=self._span(meta))

    def disable(self, meta, children):
        return ast.Disable(children[0], span=self._span(meta))

    def reset(self, meta, children):
        return ast.Reset(children[0], span=self._span(meta))

    def assign(self, meta, children):
        return ast.Assign(_name(children[0]), _name(children[1]), children[2],
                          span=self._span(meta))

    def set_var(self, meta, children):
        return ast.SetVar(_name(children[0]), children[1], span=self._span(meta))

    def var_decl(self, meta, children):
        value = children[2] if len(children) > 2 else None
        return ast.VarDecl(_name(children[0]), _name(children[1]), value,
                           span=self._span(meta))

    def attach(self, meta, children):
        return ast.Attach(_name(children[0]), _name(children[1]), span=self._span(meta))

    def detach(self, meta, children):
        return ast.Detach(_name(children[0]), span=self._span(meta))

    def emit(self, meta, children):
        return ast.Emit(_name(children[0]), span=self._span(meta))

    def log(self, meta, children):
        return ast.Log(_string(children[0]), span=self._span(meta))

    # ---- conditions ----
    def disjunction(self, meta, children):
        return ast.Or(tuple(children), span=self._span(meta))

    def conjunction(self, meta, children):
        return ast.And(tuple(children), span=self._span(meta))

    def negation(self, meta, children):
        return ast.Not(children[0], span=self._span(meta))

    def event(self, meta, children):
        return ast.EventCondition(_name(children[0]), span=self._span(meta))

    def comparison(self, meta, children):
        measure, operator, quantity = children
        return ast.Comparison(measure, str(operator), quantity, span=self._span(meta))

    def elapsed(self, meta, children):
        return ast.Elapsed(span=self._span(meta))

    def time(self, meta, children):
        return ast.Time(span=self._span(meta))

    def distance(self, meta, children):
        return ast.Distance(_name(children[0]), _name(children[1]), span=self._span(meta))

    def clearance(self, meta, children):
        return ast.Clearance(_name(children[0]), _name(children[1]), span=self._span(meta))

    def contact(self, meta, children):
        return ast.Contact(_name(children[0]), _name(children[1]), span=self._span(meta))

    def wrench(self, meta, children):
        names = _tokens(children, "NAME")
        return ast.Wrench(str(children[0]) == "torque", _name(names[0]),
                          _name(names[1]) if len(names) > 1 else None, span=self._span(meta))

    def variable(self, meta, children):
        return ast.Variable(_name(children[0]), span=self._span(meta))

    def binary(self, meta, children):
        left, operator, right = children
        return ast.Binary(str(operator), left, right, span=self._span(meta))

    def negative(self, meta, children):
        return ast.Negative(children[-1], span=self._span(meta))

    def member(self, meta, children):
        names = [_name(c) for c in children]
        region = names[1] if len(names) == 3 else None
        return ast.Member(names[0], names[-1], region, span=self._span(meta))

    # ---- values ----
    def quantity(self, meta, children):
        units = _tokens(children, "UNIT")
        return ast.Quantity(_number(children[0]), _name(units[0]) if units else None,
                            span=self._span(meta))

    def vector(self, meta, children):
        units = _tokens(children, "UNIT")
        values = tuple(_number(c) if isinstance(c, Token) else c for c in children
                       if not (isinstance(c, Token) and c.type == "UNIT"))
        return ast.Vector(values, _name(units[0]) if units else None, span=self._span(meta))

    def name_element(self, meta, children):
        return ast.NameElement(_name(children[-1]), negative=len(children) == 2,
                               span=self._span(meta))

    def offset(self, meta, children):
        return ast.Offset(_name(children[0]), children[1], span=self._span(meta))

    def call(self, meta, children):
        return ast.Call(_name(children[0]), _nodes(children[1:], ast.Argument),
                        span=self._span(meta))

    def argument(self, meta, children):
        name = _name(children[0]) if len(children) == 2 else None
        return ast.Argument(name, children[-1], span=self._span(meta))

    def reference(self, meta, children):
        return ast.Reference(_name(children[0]), span=self._span(meta))

    def string(self, meta, children):
        return ast.String(_string(children[0]), span=self._span(meta))
