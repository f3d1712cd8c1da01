"""What the checker says because a statement did not parse: about the statement's own
partial content, or about a name that such a statement declares. A syntax error is
the one thing to fix there; the rest would be noise before it.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass

from ..diagnostics import Diagnostic, SourceFile
from .syntax_errors import CONTINUED, UNCLOSED, code_of

_DECLARES = re.compile(r"\s*(?:let|task|constraint|event|behavior|state|final|region)\s+"
                       r"([A-Za-z_]\w*)")


@dataclass(frozen=True)
class Broken:
    """The lines of the statements of one file that hold a syntax error, and the names
    those statements declare."""

    path: str
    lines: frozenset[int]
    names: frozenset[str]

    @classmethod
    def of(cls, source: SourceFile, syntax: Iterable[Diagnostic]) -> "Broken":
        """The statements of ``source`` that the syntax errors ``syntax`` fall in: each
        error's line with the lines its statement goes on over (a line ending with
        ``,``, ``(``, ``[``, ``and``, ``or`` or ``not``). A block left open is not a
        broken statement: its header parsed."""
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
            declared = _DECLARES.match(code_of(source.line(first)))
            if declared:
                names.add(declared.group(1))
        return cls(source.path, frozenset(lines), frozenset(names))

    def follows(self, diagnostic: Diagnostic, source: SourceFile) -> bool:
        """Whether ``diagnostic`` of the checker is about a broken statement of this
        file or about a name one declares (its span is that name)."""
        span = diagnostic.span
        if span is None or diagnostic.file != self.path or span.file not in (None, self.path):
            return False
        if span.line in self.lines:
            return True
        if span.line != span.end_line:
            return False
        return source.line(span.line)[span.column - 1:span.end_column - 1] in self.names
