"""What the checker says because a statement did not parse: about the statement's own
partial content, or about a name that such a statement declares. A syntax error is
the one thing to fix there; the rest would be noise before it.
"""

from __future__ import annotations

import dataclasses
import difflib
import re
from collections.abc import Iterable
from dataclasses import dataclass

from ..diagnostics import Diagnostic, SourceFile
from . import ast
from .syntax_errors import CONTINUED, RESERVED, UNCLOSED, code_of

_DECLARING = ("let", "task", "constraint", "event", "behavior", "state", "final", "region")
_DECLARES = re.compile(rf"\s*(?:{'|'.join(_DECLARING)})\s+([A-Za-z_]\w*)")
_MISSPELT = re.compile(r"\s*([A-Za-z_]\w*)\s+([A-Za-z_]\w*)\s*(?:[:{(]|$)")
"""A word then a name that ends the line or opens a block, a call or a type: a
declaration whose keyword may be misspelt (``stat home {``)."""
_FINAL = re.compile(r"\s*final\b")


@dataclass(frozen=True)
class Broken:
    """The lines of the statements of one file that hold a syntax error (``syntax``),
    and the names those statements declare that the tree lacks or holds partly."""

    source: SourceFile
    syntax: frozenset[Diagnostic]
    lines: frozenset[int]
    names: frozenset[str]

    @classmethod
    def of(cls, source: SourceFile, syntax: Iterable[Diagnostic], tree: ast.Mission
           ) -> "Broken":
        """The statements of ``source`` that the syntax errors ``syntax`` fall in: each
        error's line with the lines its statement goes on over (a line ending with
        ``,``, ``(``, ``[``, ``and``, ``or`` or ``not``). A block left open is not a
        broken statement: its header parsed. A name they declare counts when ``tree``
        (what parsed) has no declaration of it there, or only a ``let`` (its value
        partial): a declaration that recovery mended is as good as any other."""
        syntax = frozenset(syntax)
        lines: set[int] = set()
        names: set[str] = set()
        for diagnostic in syntax:
            if diagnostic.span is None or diagnostic.message == UNCLOSED:
                continue
            first = last = diagnostic.span.line
            while first > 1 and CONTINUED.search(code_of(source.line(first - 1))):
                first -= 1
            while last < source.line_count and CONTINUED.search(code_of(source.line(last))):
                last += 1
            lines.update(range(first, last + 1))
            declared = _declared(code_of(source.line(first)))
            if declared:
                names.add(declared)
        if names:
            names -= {name for name, node in _declarations(tree, lines)
                      if not isinstance(node, ast.Let)}
        return cls(source, syntax, frozenset(lines), frozenset(names))

    def follows(self, diagnostic: Diagnostic) -> bool:
        """Whether ``diagnostic``, of the checker, is about a broken statement of this
        file or about a name one declares (its span is that name)."""
        span = diagnostic.span
        if span is None or diagnostic.file != self.source.path or diagnostic in self.syntax:
            return False
        if span.line in self.lines:
            return True
        if diagnostic.code == "start-is-final" and self.lines \
                and min(self.lines) < span.line and _FINAL.match(self.source.line(span.line)):
            return True     # the first state that parsed: a broken one before it came first
        if span.line != span.end_line:
            return False
        return self.source.line(span.line)[span.column - 1:span.end_column - 1] in self.names


def _declared(code: str) -> str | None:
    """The name a statement's first line declares, its keyword possibly misspelt."""
    declared = _DECLARES.match(code)
    if declared:
        return declared.group(1)
    words = _MISSPELT.match(code)
    if words and words.group(1) not in RESERVED \
            and difflib.get_close_matches(words.group(1), _DECLARING, n=1, cutoff=0.75):
        return words.group(2)
    return None


def _declarations(node, lines: frozenset[int] | set[int]):
    """``(name, declaration)`` of each declaration under ``node`` that starts on one of
    ``lines``."""
    if isinstance(node, tuple):
        for item in node:
            yield from _declarations(item, lines)
        return
    if not isinstance(node, ast.Node):
        return
    name = getattr(node, "name", None)
    if isinstance(name, ast.Name) and not isinstance(node, ast.Name) \
            and node.span.line in lines:
        yield name.text, node
    for field in dataclasses.fields(node):
        if field.name != "span":
            yield from _declarations(getattr(node, field.name), lines)
