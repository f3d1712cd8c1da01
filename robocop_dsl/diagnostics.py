"""Diagnostics: located messages about a mission or world file, and their renderings.

Every user-facing error of the tool is a :class:`Diagnostic`: a code, a message, the
file, a 1-based line/column span, the source line and an optional hint. A check pass
collects all of them; :class:`DiagnosticError` carries them out of an API call.
"""

from __future__ import annotations

import bisect
import difflib
import functools
import json
import re
import unicodedata
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Iterable, Sequence

ERROR = "error"
WARNING = "warning"
_QUOTED_WIDTH = 120


@dataclass(frozen=True, slots=True)
class Span:
    """A region of a source file: 1-based lines and columns, end column exclusive.
    ``file`` names the file when it is not the one being checked (an imported file)."""

    line: int
    column: int
    end_line: int
    end_column: int
    file: str | None = field(default=None, compare=False)

    @classmethod
    def point(cls, line: int, column: int = 1, width: int = 1) -> "Span":
        return cls(line, column, line, column + max(width, 1))

    def location(self, default: str) -> str:
        """``FILE:LINE:COL``, with ``default`` as the file when the span names none."""
        return f"{self.file or default}:{self.line}:{self.column}"


# How each parser counts lines: lark's lexer at "\n" only, PyYAML also at a lone
# "\r", U+0085, U+2028 and U+2029, XML (expat) at "\r\n", "\n" and a lone "\r".
MISSION_BREAKS = re.compile(r"\n")
YAML_BREAKS = re.compile(r"\r\n|[\n\r\x85\u2028\u2029]")
XML_BREAKS = re.compile(r"\r\n|[\n\r]")


@dataclass(frozen=True)
class SourceFile:
    """A file's path and text, for locating and quoting diagnostics; ``breaks`` matches
    a line break the way the file's parser counts them."""

    path: str
    text: str
    breaks: re.Pattern = field(default=MISSION_BREAKS, compare=False, repr=False)

    @classmethod
    def read(cls, path: str | Path) -> "SourceFile":
        """Read ``path`` through :func:`robocop_dsl.sources.read_source` (its kind from
        its extension); raises :class:`~robocop_dsl.sources.UnreadableSource`."""
        from .sources import read_source
        return read_source(path)

    @functools.cached_property
    def _starts(self) -> list[int]:
        """Offset of the first character of each line."""
        return [0, *(match.end() for match in self.breaks.finditer(self.text))]

    @property
    def line_count(self) -> int:
        """How many lines the file has (an empty last line after a break counts)."""
        return len(self._starts)

    def line(self, number: int) -> str:
        """Line ``number`` (1-based) without its break, or ``""``."""
        starts = self._starts
        if not 0 < number <= len(starts):
            return ""
        end = starts[number] if number < len(starts) else len(self.text)
        line = self.text[starts[number - 1]:end]
        match = self.breaks.search(line)
        return line[:match.start()] if match else line

    def position(self, offset: int) -> tuple[int, int]:
        """The 1-based line and column of character ``offset``."""
        index = bisect.bisect_right(self._starts, offset) - 1
        return index + 1, offset - self._starts[index] + 1

    def offset(self, line: int, column: int) -> int:
        """The character offset of 1-based ``line`` and ``column`` (see :meth:`position`)."""
        return self._starts[line - 1] + column - 1

    def error(self, code: str, message: str, span: Span | None, hint: str | None = None,
              severity: str = ERROR, notes: tuple[str, ...] = ()) -> "Diagnostic":
        """Build a diagnostic located in this file."""
        source_line = self.line(span.line) if span else ""
        return Diagnostic(code, message, self.path, span, severity, hint, source_line,
                          notes)

    def warning(self, code: str, message: str, span: Span | None,
                hint: str | None = None, notes: tuple[str, ...] = ()) -> "Diagnostic":
        return self.error(code, message, span, hint, WARNING, notes)


@dataclass(frozen=True)
class Diagnostic:
    """One located message. ``severity`` is ``"error"`` or ``"warning"``."""

    code: str
    message: str
    file: str
    span: Span | None
    severity: str = ERROR
    hint: str | None = None
    source_line: str = ""
    notes: tuple[str, ...] = ()

    @property
    def is_error(self) -> bool:
        return self.severity == ERROR

    def location(self) -> str:
        if self.span is None:
            return self.file
        return f"{self.file}:{self.span.line}:{self.span.column}"

    def headline(self) -> str:
        return f"{self.location()}: {self.severity}[{self.code}]: {self.message}"

    def render(self) -> str:
        """gcc-style text: headline, source line, caret under the span, hint."""
        lines = [self.headline()]
        if self.span is not None and self.source_line:
            number = str(self.span.line)
            gutter = " " * len(number)
            text = _printable(self.source_line.expandtabs(1))
            start = self.span.column - 1
            if self.span.end_line == self.span.line:
                end = max(self.span.end_column - 1, start + 1)
            else:
                end = max(len(text.rstrip()), start + 1)
            if len(text) > _QUOTED_WIDTH:
                text, start, end = _window(text, start, end)
            lines.append(f" {number} | {text}")
            lines.append(f" {gutter} | {' ' * start}{'^' * (end - start)}")
        if self.hint:
            lines.append(f"   = hint: {self.hint}")
        lines += [f"   = note: {note}" for note in self.notes]
        return "\n".join(lines)

    def to_json(self) -> dict:
        data = asdict(self)
        data["span"] = ({k: v for k, v in asdict(self.span).items() if k != "file"}
                        if self.span else None)
        data["notes"] = list(self.notes)
        return data

    def to_github(self) -> str:
        """A GitHub Actions workflow command that annotates the line in a pull request."""
        kind = "error" if self.is_error else "warning"
        props = [f"file={_github_property(self.file)}"]
        if self.span is not None:
            props += [f"line={self.span.line}", f"col={self.span.column}",
                      f"endLine={self.span.end_line}", f"endColumn={self.span.end_column}"]
        props.append(f"title={_github_property(self.code)}")
        message = self.message + (f" (hint: {self.hint})" if self.hint else "")
        message += "".join(f" (note: {note})" for note in self.notes)
        return f"::{kind} {','.join(props)}::{_github_data(message)}"


def _github_data(text: str) -> str:
    """``text`` escaped as a workflow command's message."""
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def _github_property(text: str) -> str:
    """``text`` escaped as a workflow command's property value."""
    return _github_data(text).replace(":", "%3A").replace(",", "%2C")


def _window(text: str, start: int, end: int) -> tuple[str, int, int]:
    """A :data:`_QUOTED_WIDTH`-character piece of a long line around columns
    ``start:end`` (0-based), "..." marking the cuts; the columns shifted to match."""
    end = min(end, start + _QUOTED_WIDTH // 2)
    first = max(0, min(start - _QUOTED_WIDTH // 4, len(text) - _QUOTED_WIDTH))
    piece = text[first:first + _QUOTED_WIDTH]
    lead = "..." if first else ""
    tail = "..." if first + _QUOTED_WIDTH < len(text) else ""
    shift = len(lead) - first
    return lead + piece + tail, start + shift, end + shift


def _printable(line: str) -> str:
    """``line`` with each control, format or line-separator character shown as U+FFFD,
    one column each, so that a quoted line stays one line and the caret stays aligned."""
    return "".join("\ufffd" if unicodedata.category(c) in ("Cc", "Cf", "Zl", "Zp") else c
                   for c in line)


class RobocopError(Exception):
    """Root of the package's exceptions."""


class DiagnosticError(RobocopError):
    """Raised by API calls that found errors in user input; carries every diagnostic."""

    def __init__(self, diagnostics: Sequence[Diagnostic]):
        self.diagnostics = list(diagnostics)
        super().__init__("\n".join(d.render() for d in self.diagnostics))


def did_you_mean(name: str, candidates: Iterable[str]) -> str | None:
    """A hint naming the closest candidates to ``name``, or ``None``."""
    scored = [(difflib.SequenceMatcher(None, name, c).ratio(), c) for c in set(candidates)]
    scored = [(score, c) for score, c in scored if score >= 0.6]
    if not scored:
        return None
    best = max(score for score, _ in scored)
    close = sorted(c for score, c in scored if score >= best - 1e-9)[:3]
    if len(close) == 1:
        return f"did you mean '{close[0]}'?"
    return "did you mean " + ", ".join(f"'{c}'" for c in close[:-1]) + f" or '{close[-1]}'?"


def render_all(diagnostics: Sequence[Diagnostic], fmt: str = "text") -> str:
    """Render diagnostics as ``text``, ``json`` or ``github``."""
    if fmt == "json":
        return json.dumps([d.to_json() for d in diagnostics], indent=2)
    if fmt == "github":
        return "\n".join(d.to_github() for d in diagnostics)
    return "\n\n".join(d.render() for d in diagnostics)


def unique(diagnostics: Iterable[Diagnostic]) -> list[Diagnostic]:
    """``diagnostics`` without repeats of one message at one place (a problem inside a
    behaviour exposed by several instances is reported once, with the first's note)."""
    seen, kept = set(), []
    for diagnostic in diagnostics:
        key = (diagnostic.file, diagnostic.span, diagnostic.code, diagnostic.message)
        if key not in seen:
            seen.add(key)
            kept.append(diagnostic)
    return kept


def sort_key(diagnostic: Diagnostic) -> tuple:
    span = diagnostic.span
    return (diagnostic.file, span.line if span else 0, span.column if span else 0,
            diagnostic.code)
