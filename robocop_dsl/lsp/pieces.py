"""Parsing a mission piece by piece, so that an edit reparses the piece it is in only.

The text is cut before a top-level statement that begins a line outside every block
(braces counted outside strings and comments) and does not continue the line before
(one that ends with ``,``, ``(``, ``[``, ``and``, ``or`` or ``not``), into pieces of at
least :data:`PIECE_LINES` lines. Each piece is parsed on its own and kept by its text;
the mission is the pieces' items in order, with the spans they have in the whole text:
the tree :func:`~robocop_dsl.lang.parse_mission` gives for the whole text. Each piece is
parsed where it stands in the file, so that the lines its spans and diagnostics name
are the file's.
"""

from __future__ import annotations

import dataclasses
import re
from typing import Callable

from ..check import Cancelled
from ..check.rewrite import child_fields, replace
from ..diagnostics import SourceFile, Span
from ..lang import ParseResult, ast, parse_mission
from ..lang.syntax_errors import CONTINUED, code_of

PIECE_LINES = 200
_STATEMENT = re.compile(r"\s*(mission|library|import|let|var|world|controller|task|constraint"
                        r"|event|behavior|start|state|final|when)\b")


def pieces(text: str) -> list[tuple[int, str]]:
    """The pieces of ``text``: each one's first line (1-based) and text; joined, they
    are ``text``."""
    lines = text.split("\n")
    found, start, depth, continued = [], 0, 0, False
    for number, line in enumerate(lines):
        if (depth == 0 and not continued and number - start >= PIECE_LINES
                and _STATEMENT.match(line)):
            found.append((start + 1, "\n".join(lines[start:number]) + "\n"))
            start = number
        code = code_of(line)
        depth = max(depth + code.count("{") - code.count("}"), 0)
        continued = bool(CONTINUED.search(code))
    found.append((start + 1, "\n".join(lines[start:])))
    return found


def _shift(span: Span, lines: int) -> Span:
    if span.line <= 0:
        return span
    return Span(span.line + lines, span.column, span.end_line + lines, span.end_column,
                span.file)


def _moved(node, lines: int):
    """A copy of ``node`` with every span moved down by ``lines``."""
    if isinstance(node, tuple):
        return tuple(_moved(item, lines) for item in node)
    if not isinstance(node, ast.Node):
        return node
    changes = {name: _moved(getattr(node, name), lines) for name in child_fields(type(node))}
    return replace(node, span=_shift(node.span, lines), **changes)


class PieceCache:
    """The parsed pieces of one file's last parse, by text; :meth:`parse` reuses them."""

    def __init__(self):
        self._known: dict[str, tuple[int, ParseResult]] = {}

    def parse(self, text: str, path: str,
              cancelled: Callable[[], bool] = lambda: False) -> ParseResult:
        """The parse of ``text``: its pieces parsed anew where their text changed, moved
        where only their place did.

        Raises:
            Cancelled: ``cancelled()`` was true before a piece was parsed (the pieces
                parsed so far are kept for the next parse).
        """
        known, kept = self._known, {}
        items: list = []
        found: list = []
        for first, piece in pieces(text):
            if piece not in known and cancelled():
                self._known = {**known, **kept}
                raise Cancelled()
            result = self._piece(known.get(piece), first, piece, path)
            kept[piece] = (first, result)
            items += result.mission.items
            found += result.diagnostics
        self._known = kept
        last = text.count("\n") + 1
        mission = ast.Mission(tuple(items), span=Span(1, 1, last, 1))
        return ParseResult(mission, tuple(found), SourceFile(path, text))

    @staticmethod
    def _piece(known: tuple[int, ParseResult] | None, first: int, piece: str,
               path: str) -> ParseResult:
        if known is None or (known[0] != first and known[1].diagnostics):
            return parse_mission(piece, path, first)
        at, result = known
        if at == first:
            return result
        return dataclasses.replace(result, mission=_moved(result.mission, first - at))
