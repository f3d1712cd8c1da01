"""Quick fixes: the edits a diagnostic's own words call for.

A "did you mean 'X'?" hint replaces the name its message quotes, inside the
diagnostic's span, with X (one fix per name offered: ``'a', 'b' or 'c'``), or, when
the name came from a behaviour's argument (a note "in CALL at FILE:LINE:COL"), in that
argument of the instance; a missing
``->``, ``=``, ``:``, ``)`` or ``]`` is inserted where it was expected, a ``:`` written
for ``=`` (or the reverse) is replaced, two statements on one line are split, and a
block left open is closed where its indentation shows it ends (a ``}`` on a line of
its own, indented like the line of its ``{``).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from ..diagnostics import Diagnostic, RobocopError, SourceFile, Span
from ..lang.syntax_errors import UNCLOSED, code_of, layout_closings

_SUGGESTION = re.compile(r"did you mean ((?:'[^']*'(?:, | or )?)+)\?")
_QUOTED = re.compile(r"'([^']*)'")
_MISSING = re.compile(r"missing '([^']+)' before (.+)")
_WRONG = re.compile(r"expected '([^']+)' here, not '([^']+)'")
_NEW_LINE = "expected a new line before"
_INSTANCE = re.compile(r"^in .* at (.+):(\d+):(\d+)$")


@dataclass(frozen=True)
class Fix:
    """Replace ``span`` of ``path`` (an empty span: insert there) with ``text``."""

    title: str
    path: Path
    span: Span
    text: str
    preferred: bool = False


def fixes(diagnostic: Diagnostic, path: Path, source: SourceFile | None) -> list[Fix]:
    """The fixes of ``diagnostic``, located in ``path`` whose text is ``source``."""
    span = diagnostic.span
    if source is None or span is None or span.line <= 0 or span.end_line != span.line:
        return []
    if diagnostic.hint and _SUGGESTION.search(diagnostic.hint):
        return _suggested(diagnostic, path, source)
    if diagnostic.code == "missing-token":
        return _inserted(diagnostic, path, source)
    if diagnostic.code == "wrong-token":
        wrong = _WRONG.match(diagnostic.message)
        return [_replaced(wrong.group(1), path, source, span)] if wrong else []
    return []


def _replaced(token: str, path: Path, source: SourceFile, span: Span) -> Fix:
    """``token`` written where the span's token is, spaced as the language is written:
    ``NAME = VALUE``, ``NAME: TYPE``."""
    before = source.line(span.line)[:span.column - 1]
    if token == ":":
        start = len(before.rstrip()) + 1
        return Fix("write ':'", path, Span(span.line, start, span.line, span.end_column), ":",
                   True)
    return Fix(f"write '{token}'", path, span, ("" if before.endswith(" ") else " ") + token,
               True)


def _suggested(diagnostic: Diagnostic, path: Path, source: SourceFile) -> list[Fix]:
    """One fix per name a "did you mean" hint offers, replacing the name the message
    quotes first (found in the span's text, else in the behaviour instance a note
    names)."""
    quoted = _QUOTED.search(diagnostic.message)
    if quoted is None or not quoted.group(1):
        return []
    wrong = quoted.group(1)
    place = _written(wrong, path, source, diagnostic.span) or _in_instance(wrong, diagnostic,
                                                                          path, source)
    if place is None:
        return []
    at, span, written = place
    names = _QUOTED.findall(_SUGGESTION.search(diagnostic.hint).group(1))
    return [Fix(f"change '{wrong}' to '{name}'", at, span, written.replace(wrong, name, 1),
                len(names) == 1)
            for name in names]


def _written(name: str, path: Path, source: SourceFile, span: Span):
    """``(path, span, text)`` of ``span`` when its text holds ``name``."""
    written = source.line(span.line)[span.column - 1:span.end_column - 1]
    return (path, span, written) if name in written else None


def _in_instance(name: str, diagnostic: Diagnostic, path: Path, source: SourceFile):
    """``(path, span, name)`` of ``name`` as an argument of the behaviour instance a
    note of ``diagnostic`` names, or ``None``."""
    for note in diagnostic.notes:
        found = _INSTANCE.match(note)
        if found is None:
            continue
        at, line, column = Path(found.group(1)).resolve(), int(found.group(2)), \
            int(found.group(3))
        if at != path:
            try:
                source = SourceFile.read(at)
            except RobocopError:
                continue
        text = source.line(line)
        argument = re.compile(rf"\b{re.escape(name)}\b").search(text, column - 1)
        if argument is not None:
            return at, Span(line, argument.start() + 1, line, argument.end() + 1), name
    return None


def _inserted(diagnostic: Diagnostic, path: Path, source: SourceFile) -> list[Fix]:
    span = diagnostic.span
    line = source.line(span.line)
    if diagnostic.message == UNCLOSED:
        closing = next((c for c in layout_closings(source.text)
                        if (c.line, c.column) == (span.line, span.column)), None)
        if closing is None:
            return []
        end = len(code_of(source.line(closing.at)).rstrip()) + 1
        opening = source.line(closing.line)
        brace = "\n" + opening[:len(opening) - len(opening.lstrip())] + "}"
        return [Fix("close the block", path, Span(closing.at, end, closing.at, end), brace,
                    True)]
    if diagnostic.message.startswith(_NEW_LINE):
        indent = line[:len(line) - len(line.lstrip())]
        start = len(line[:span.column - 1].rstrip()) + 1
        return [Fix("start a new line", path, Span(span.line, start, span.line, span.column),
                    "\n" + indent, True)]
    missing = _MISSING.match(diagnostic.message)
    if missing is None:
        return []
    token = missing.group(1)
    if missing.group(2) == "end of line":
        column = len(code_of(line).rstrip()) + 1
        return [Fix(f"insert '{token}'", path, Span(span.line, column, span.line, column),
                    token, True)]
    return [Fix(f"insert '{token}'", path, Span(span.line, span.column, span.line, span.column),
                token + " ", True)]
