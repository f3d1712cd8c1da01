"""Parse mission text into the syntax tree, reporting every syntax error found.

The grammar is ``mission.lark`` from the shipped grammar folder, loaded once (LALR,
positions propagated). Newlines end statements; :class:`StatementBreaks` drops the
ones inside brackets so long vectors and calls may span lines.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

from lark import Lark, Token
from lark.exceptions import LarkError, VisitError
from lark.lark import PostLex

from ..diagnostics import Diagnostic, SourceFile, Span
from ..resources import GRAMMAR_DIR
from . import ast
from .syntax_errors import RESERVED, Recovery
from .transformer import MissionBuilder

_BREAKABLE_AFTER = ("COMMA", "LPAR", "LSQB")
_OPERATORS = ("AND", "OR", "NOT")


class StatementBreaks(PostLex):
    """Drop newlines inside ``[]`` and ``()``, merge repeated ones, end the file with one,
    and give reserved words their keyword type wherever they appear.

    A line may break after ``and``, ``or`` and ``not``, and inside brackets after ``(``,
    ``[`` or ``,``; any other newline ends the statement and forgets the brackets, so a
    missing ``]`` does not swallow the following lines.
    """

    always_accept = ("_NL",)

    def process(self, stream):
        brackets = 0
        last: Token | None = None
        for token in stream:
            if token.type in ("NAME", "UNIT") and token.value in RESERVED:
                token = Token.new_borrow_pos(token.value.upper(), token.value, token)
            if token.type == "_NL":
                if last is not None and (last.type in _OPERATORS or
                                         (brackets and last.type in _BREAKABLE_AFTER)):
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
    """The mission parser, built once from ``mission.lark``; lark caches the built
    tables in the temporary folder (keyed by the grammar's hash) for the next process."""
    return Lark((GRAMMAR_DIR / "mission.lark").read_text(encoding="utf-8"),
                parser="lalr", lexer="contextual", propagate_positions=True,
                postlex=StatementBreaks(), import_paths=[GRAMMAR_DIR], cache=True)


@dataclass(frozen=True)
class ParseResult:
    """What parsing a mission gave: the tree of what parsed and every syntax error."""

    mission: ast.Mission
    diagnostics: tuple[Diagnostic, ...]
    source: SourceFile

    @property
    def ok(self) -> bool:
        return not any(d.is_error for d in self.diagnostics)


def parse_mission(text: str, path: str | Path = "<mission>") -> ParseResult:
    """Parse mission ``text``; never raises on bad input, diagnostics say what is wrong."""
    source = SourceFile(str(path), text)
    recovery = Recovery(source, mission_grammar())
    try:
        tree = mission_grammar().parse(text, on_error=recovery)
        mission = MissionBuilder(text).transform(tree)
    except (LarkError, VisitError) as error:
        recovery.give_up(error)
        mission = ast.Mission(span=Span.point(1))
    return ParseResult(mission, tuple(recovery.diagnostics), source)


def parse_file(path: str | Path) -> ParseResult:
    """Read and parse a mission file (UTF-8)."""
    return parse_mission(Path(path).read_text(encoding="utf-8"), path)
