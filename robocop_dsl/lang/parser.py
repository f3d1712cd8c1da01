"""Parse mission text into the syntax tree, reporting every syntax error found.

The grammar is ``mission.lark`` from the shipped grammar folder, loaded once (LALR,
positions propagated). Newlines end statements; :class:`StatementBreaks` drops the
ones inside brackets so long vectors and calls may span lines.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import sys
import threading
from dataclasses import dataclass
from pathlib import Path

import lark
from lark import Lark, Token, Tree
from lark.exceptions import LarkError, VisitError
from lark.lark import PostLex

from ..diagnostics import Diagnostic, SourceFile, Span
from ..resources import GRAMMAR_DIR, private_cache_file
from ..sources import MISSION, editor_lines, read_source
from . import ast
from .syntax_errors import (LINE_STARTS, RESERVED, UNCLOSED, Recovery, closed_by_layout,
                            closing_places, code_of, layout_closings)
from .transformer import MissionBuilder

# Syntax-tree depth beyond which a statement is refused (the rest of the file is read):
# the checker and the compiler walk the tree recursively; real missions nest about 12
# deep, a sum of 190 terms about 200.
MAX_NESTING = 200
_BREAKABLE_AFTER = ("COMMA", "LPAR", "LSQB")
_OPERATORS = ("AND", "OR", "NOT")
_STATEMENT_STARTS = frozenset(word.upper() for word in LINE_STARTS) | {"RBRACE"}
"""The token types of :data:`~.syntax_errors.LINE_STARTS` and ``}``."""
_PLACE = threading.local()
"""``lines``: how many lines come before the text this thread parses now."""


class StatementBreaks(PostLex):
    """Drop newlines inside ``[]`` and ``()``, merge repeated ones, end the file with one,
    and give reserved words their keyword type wherever they appear.

    A line may break after ``and``, ``or`` and ``not``, and inside brackets after ``(``,
    ``[`` or ``,``, unless the next line begins with a statement's keyword or ``}`` (the
    line was left unfinished); a break before a line that starts with ``]`` or ``)`` never
    reaches this (the grammar ignores it); any other newline ends the statement and
    forgets the brackets, so a missing ``]`` does not swallow the following lines.
    """

    always_accept = ("_NL", "NAME")

    def process(self, stream):
        brackets = 0
        last: Token | None = None
        held: Token | None = None       # a line break after an operator or a comma
        lines_before = getattr(_PLACE, "lines", 0)
        for token in stream:
            if lines_before:
                token.line += lines_before
                token.end_line += lines_before
            if token.type in ("NAME", "UNIT") and token.value in RESERVED:
                token = Token.new_borrow_pos(token.value.upper(), token.value, token)
            if held is not None and token.type in _STATEMENT_STARTS:
                yield held              # the line before was left unfinished
                brackets, last = 0, held
            held = None
            if token.type == "_NL":
                if last is not None and (last.type in _OPERATORS or
                                         (brackets and last.type in _BREAKABLE_AFTER)):
                    held = token
                    continue
                brackets = 0
                if last is not None and last.type == "_NL":
                    continue
            elif token.type in ("LSQB", "LPAR"):
                brackets += 1
            elif token.type in ("RSQB", "RPAR"):
                brackets = max(brackets - 1, 0)
            elif token.type in ("LBRACE", "RBRACE"):
                brackets = 0
            last = token
            yield token
        if last is not None and last.type != "_NL":
            yield Token.new_borrow_pos("_NL", "", last)


@functools.lru_cache(maxsize=None)
def mission_grammar() -> Lark:
    """The mission parser, built once from ``mission.lark`` (see :func:`build_parser`)."""
    return build_parser((GRAMMAR_DIR / "mission.lark").read_text(encoding="utf-8"))


def build_parser(grammar: str) -> Lark:
    """A parser of the grammar text ``grammar``. Its tables are kept for the next
    process only in the user's private cache folder (:func:`private_cache`), in a file
    named after the grammar's text: a changed grammar never meets old tables. Lark
    unpickles its cache file, so a file others can write would run their code; a
    folder that cannot be written only costs building the tables each time."""
    return Lark(grammar, parser="lalr", lexer="contextual", propagate_positions=True,
                postlex=StatementBreaks(), import_paths=[GRAMMAR_DIR],
                cache=private_cache(grammar))


def private_cache(grammar: str) -> str | bool:
    """The parser cache file for ``grammar`` in the user's private cache folder
    (:func:`~robocop_dsl.resources.private_cache_file`), named after the grammar's text,
    lark's version and Python's, or ``False`` (no cache) when that folder is not private."""
    key = f"{grammar}{lark.__version__}{sys.version_info[:2]}"
    digest = hashlib.sha256(key.encode()).hexdigest()[:24]
    return private_cache_file(f"mission-grammar-{digest}.lark") or False


@dataclass(frozen=True)
class ParseResult:
    """What parsing a mission gave: the tree of what parsed and every syntax error."""

    mission: ast.Mission
    diagnostics: tuple[Diagnostic, ...]
    source: SourceFile

    @property
    def ok(self) -> bool:
        return not any(d.is_error for d in self.diagnostics)


def parse_mission(text: str, path: str | Path = "<mission>",
                  first_line: int = 1) -> ParseResult:
    """Parse mission ``text``; never raises on bad input, diagnostics say what is wrong
    (in the order of their places). ``text`` is the part of the file at ``path`` that
    begins on line ``first_line``: spans and diagnostics name the file's lines."""
    if first_line > 1:
        _PLACE.lines = first_line - 1
        try:
            placed = parse_mission(text, path)
        finally:
            _PLACE.lines = 0
        if not placed.diagnostics:
            return placed
        padded = parse_mission("\n" * (first_line - 1) + text, path)
        return dataclasses.replace(padded, source=placed.source)
    text = editor_lines(text)
    source = SourceFile(str(path), text)
    mission, diagnostics, unclosed = _parse(text, source)
    if unclosed:
        mission, diagnostics = _closed_by_layout(text, source, mission, diagnostics, unclosed)
    ordered = sorted(diagnostics, key=lambda d: (d.span.line, d.span.column) if d.span
                     else (0, 0))
    return ParseResult(mission, tuple(ordered), source)


def _parse(text: str, source: SourceFile) -> tuple[ast.Mission, list[Diagnostic], int]:
    """The tree of what parsed, the syntax errors and how many blocks recovery closed."""
    recovery = Recovery(source, mission_grammar())
    mission = ast.Mission(span=Span.point(1))
    try:
        tree = mission_grammar().parse(text, on_error=recovery)
        kept = []
        for item in tree.children:
            too_deep = _too_deep(item, 2) if isinstance(item, Tree) else None
            if too_deep is None:
                kept.append(item)
                continue
            recovery.diagnostics.append(source.error(
                "syntax-error", f"nested more than {MAX_NESTING} levels deep", too_deep,
                "give parts of the condition or of the state machine names of their own "
                "(a 'let', a behaviour, a state)"))
        tree.children = kept
        mission = MissionBuilder(text).transform(tree)
    except (LarkError, VisitError) as error:
        recovery.give_up(error)
    return mission, recovery.diagnostics, len(recovery.unclosed)


def _closed_by_layout(text: str, source: SourceFile, mission: ast.Mission,
                      diagnostics: list[Diagnostic], unclosed: int):
    """The parse of ``text`` with each block that its indentation shows to be over
    closed where it ends (the statements after it stay out of it), when that parse
    leaves no block open, has no more errors than the first and finds nothing wrong
    with an added ``}`` but where the block's last statement was found broken by the
    first (a ``}`` after a half-typed statement: that statement keeps the first parse's
    error), else the first."""
    closings = layout_closings(text)
    if not closings:
        return mission, diagnostics
    places = closing_places(text, closings)
    patched = closed_by_layout(text, places)
    second, found, still_open = _parse(patched, SourceFile(source.path, patched))
    ends = {at: len(code_of(source.line(at)).rstrip()) for at in places}
    on_added = {d.span.line for d in found
                if d.span and d.span.column > ends.get(d.span.line, d.span.column)}
    broken = {d.span.line: d for d in diagnostics if d.span and d.message != UNCLOSED}
    kept = {line for added in on_added for line in [added] + [c.at for c in places[added]]
            if line in broken}
    if (still_open or any(not {added, *(c.at for c in places[added])} & kept
                          for added in on_added)
            or len(found) > len(diagnostics) - unclosed):
        return mission, diagnostics
    quoted = [dataclasses.replace(d, source_line=source.line(d.span.line)) if d.span else d
              for d in found if not (d.span and d.span.line in on_added | kept)]
    quoted += [broken[line] for line in sorted(kept)]
    return second, quoted + [source.error("missing-token", UNCLOSED,
                                          Span.point(c.line, c.column), c.hint)
                             for c in closings]


def parse_file(path: str | Path) -> ParseResult:
    """Read and parse a mission file (see :func:`robocop_dsl.sources.read_source`).

    Raises:
        UnreadableSource: the file is refused or cannot be read.
    """
    return parse_mission(read_source(path, MISSION).text, path)


def _too_deep(tree: Tree, depth: int = 1) -> Span | None:
    """Where ``tree`` (at ``depth``) first nests deeper than :data:`MAX_NESTING`, or
    ``None``."""
    stack = [(tree, depth)]
    while stack:
        node, depth = stack.pop()
        if depth > MAX_NESTING:
            start = node.meta if isinstance(node, Tree) and not node.meta.empty else node
            return Span.point(getattr(start, "line", 1) or 1, getattr(start, "column", 1) or 1)
        if isinstance(node, Tree):
            stack += [(child, depth + 1) for child in reversed(node.children)]
    return None
