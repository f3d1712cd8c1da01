"""A rename tried before it is answered: every file that sees the renamed declaration
is checked with the new name written in (the open documents' unsaved texts too), and a
rename that makes an error appear that was not there is refused, naming that error. It
finds the clashes the naming rules of :mod:`.navigation` do not: a constant of a
library's importer, a task that a behaviour's body names, a world body."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

from ..diagnostics import Diagnostic, SourceFile, Span
from ..lang.parser import parse_mission
from . import checking
from .project import Parsed, Project


def new_error(project: Project, places: list, seeing: list[Path],
              new_name: str) -> Diagnostic | None:
    """The first error that writing ``new_name`` at ``places`` (``(path, occurrence)``
    pairs) makes appear in the files of ``seeing``, or ``None``."""
    spans: dict[Path, list[Span]] = {}
    for path, occurrence in places:
        spans.setdefault(path, []).append(occurrence.name.span)
    texts = dict(project.open)
    for path, at in spans.items():
        text = project.text(path)
        if text is not None:
            texts[path] = _renamed(text, at, new_name)
    for path in dict.fromkeys([*spans, *seeing]):
        text = project.text(path)
        if text is None:
            continue
        before = _errors(project, path, text, dict(project.open))
        after = _errors(project, path, texts.get(path, text), texts)
        found = _first_new(before, after)
        if found is not None:
            return found
    return None


def _renamed(text: str, spans: list[Span], new_name: str) -> str:
    """``text`` with ``new_name`` written over each of ``spans`` (one line each)."""
    source = SourceFile("", text)
    for span in sorted(spans, key=lambda s: (s.line, s.column), reverse=True):
        start = source.offset(span.line, span.column)
        end = source.offset(span.end_line, span.end_column)
        text = text[:start] + new_name + text[end:]
    return text


def _errors(project: Project, path: Path, text: str, texts: dict) -> list[Diagnostic]:
    parsed = Parsed(path, text, parse_mission(text, path))
    found = checking.check(project, parsed, texts=texts) or []
    return [d for d in found if d.is_error]


def _first_new(before: list[Diagnostic], after: list[Diagnostic]) -> Diagnostic | None:
    """The first error of ``after`` beyond the number of its kind in ``before``."""
    known = Counter(d.code for d in before)
    for diagnostic in after:
        if known[diagnostic.code]:
            known[diagnostic.code] -= 1
        else:
            return diagnostic
    return None
