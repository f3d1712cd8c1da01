"""The author's layout that formatting a mission's text keeps, where it carries meaning.

The formatter prints :class:`Line` objects, each with the source line it prints. Given
the source, the passes here keep: the blank lines the author put between statements
(one at most); a block of one action written on one line (``enter { enable arms }``),
when it fits in :data:`WIDTH` columns; the rows of a vector written over several lines,
each row after the first under the first element (one level deeper than the line that
opens the vector, when its ``[`` ends that line) and a ``]`` the author began a line
with under that line; the column of ``=``, ``->`` or a
one-line block's ``{`` that adjacent statements share, and that of trailing comments
(each at its own column, adjacent ones aligned); and every comment, where its reader
expects it.
"""

from __future__ import annotations

import dataclasses
import re
from dataclasses import dataclass

from .syntax_errors import code_of, comment_start

WIDTH = 100
"""The widest a block of one action may be kept on one line [columns]."""
SET_APART = 4
"""Spaces between code and a trailing comment from which the comment's column is the
author's choice, kept."""
ROW_BREAK = "\n"
"""Between the rows of a vector in a printed line, until they are made lines."""
_ANCHORS = {":": re.compile(r"^\s*var\s+\w+:\s*(\S)"), "=": re.compile(r" (=) "),
            "->": re.compile(r" (->) "), "{": re.compile(r" (\{)")}
"""Where each kind of anchor is in a line's code: the first group's start."""


@dataclass(frozen=True)
class Line:
    """One output line and the source line it prints (0 for a blank line the formatter
    adds). ``anchors`` are the columns adjacent lines may align, left to right (``:``
    for the type of a ``var``, then ``=``, ``->`` or ``{``); ``joinable`` marks the
    header of a block of one action that was written on one line; ``row`` a vector's
    row after the first."""

    text: str
    origin: int = 0
    anchors: tuple[str, ...] = ()
    joinable: bool = False
    row: bool = False


BLANK = Line("")


@dataclass(frozen=True)
class Comment:
    """A ``#`` comment: its 1-based line, its text, whether code precedes it and the
    0-based column where it starts."""

    line: int
    text: str
    after_code: bool
    column: int = 0


def comments(text: str) -> list[Comment]:
    """Every comment of mission ``text`` (a ``#`` inside a string is no comment)."""
    found = []
    for number, line in enumerate(text.split("\n"), 1):
        start = comment_start(line)
        if start is not None:
            found.append(Comment(number, line[start:].rstrip(), bool(line[:start].strip()),
                                 start))
    return found


def _blank(source: list[str], number: int) -> bool:
    return 0 < number <= len(source) and not source[number - 1].strip()


def vector_separators(source: list[str], start: tuple[int, int], end: tuple[int, int]
                      ) -> list[str] | None:
    """What goes before each element of a vector written from ``start`` to ``end``
    (1-based line and column, end exclusive) to keep its author's layout: the spaces
    after ``[`` and after each comma (one at least), or :data:`ROW_BREAK` (after a
    comma but for the first) where the element is on a later line; then what goes
    before its ``]``: :data:`ROW_BREAK` where the author began a line with it, else
    nothing. ``None`` when the vector is written on one line with single spaces."""
    rows = [source[start[0] - 1][start[1] - 1:end[1] - 1]] if start[0] == end[0] else \
        [source[start[0] - 1][start[1] - 1:]] + source[start[0]:end[0] - 1] \
        + [source[end[0] - 1][:end[1] - 1]]
    separators: list[str] = []
    for number, row in enumerate(rows):
        code = code_of(row).split("]")[0]
        pieces = (code.split("[", 1)[1] if number == 0 else code).split(",")
        for index, piece in enumerate(pieces):
            if not piece.strip():
                continue
            spaces = " " * (len(piece) - len(piece.lstrip()))
            if not separators:
                separators.append(spaces if number == 0 else ROW_BREAK)
            elif index == 0:
                separators.append("," + ROW_BREAK)
            else:
                separators.append("," + (spaces or " "))
    closing = ROW_BREAK if len(rows) > 1 and not code_of(rows[-1]).split("]")[0].strip() \
        else ""
    plain = separators[:1] == [""] and all(s == ", " for s in separators[1:])
    return None if plain and not closing else separators + [closing]


def with_author_blanks(lines: list[Line], source: list[str]) -> list[Line]:
    """``lines`` with a blank line between two of them (statements, or rows of one)
    where the source has one."""
    out: list[Line] = []
    previous = 0
    for line in lines:
        if previous and line.origin > previous + 1:
            out += [Line("", n) for n in range(previous + 1, line.origin)
                    if _blank(source, n) and not _blank(source, n - 1)]
        out.append(line)
        previous = line.origin or previous
    return out


def joined(lines: list[Line]) -> list[Line]:
    """A block of one action written on one line, on one line again when it fits."""
    out: list[Line] = []
    index = 0
    while index < len(lines):
        line = lines[index]
        if line.joinable and index + 2 < len(lines) and lines[index + 2].text.strip() == "}":
            text = f"{line.text} {lines[index + 1].text.strip()} }}"
            if len(text) <= WIDTH and ROW_BREAK not in text:
                out.append(dataclasses.replace(line, text=text, joinable=False,
                                               anchors=line.anchors or ("{",)))
                index += 3
                continue
        out.append(line)
        index += 1
    return out


def _anchor_column(text: str, anchor: str) -> int | None:
    """Where what ``anchor`` aligns starts in ``text`` (0-based), outside strings."""
    found = _ANCHORS[anchor].search(code_of(text))
    return None if found is None else found.start(1)


def aligned(lines: list[Line], source: list[str]) -> list[Line]:
    """Adjacent statements whose anchors the author aligned, aligned again, each kind
    in turn: at the author's column, or further when a statement now needs it."""
    out = list(lines)
    for anchor in _ANCHORS:
        index = 0
        while index < len(out):
            group = _group(out, index, source, anchor)
            if len(group) > 1:
                wanted = _anchor_column(source[out[index].origin - 1], anchor)
                needed = max(len(out[i].text[:_anchor_column(out[i].text, anchor)].rstrip())
                             + 1 for i in group)
                for i in group:
                    text = out[i].text
                    at = _anchor_column(text, anchor)
                    column = max(wanted, needed)
                    out[i] = dataclasses.replace(
                        out[i], text=text[:at].rstrip().ljust(column) + text[at:])
            index += max(len(group), 1)
    return out


def _group(lines: list[Line], start: int, source: list[str], anchor: str) -> list[int]:
    """The lines from ``start`` on whose ``anchor`` was at one column in adjacent source
    lines (nothing but the first statement's own lines between them)."""
    first = lines[start]
    if anchor not in first.anchors or not first.origin:
        return []
    column = _anchor_column(source[first.origin - 1], anchor)
    group = [start]
    for index in range(start + 1, len(lines)):
        line, previous = lines[index], lines[index - 1]
        if (anchor not in line.anchors or not line.origin or column is None
                or _anchor_column(source[line.origin - 1], anchor) != column
                or any(not code_of(source[n - 1]).strip()
                       for n in range(previous.origin + 1, line.origin))):
            break
        group.append(index)
    return group


def rows_split(lines: list[Line], source: list[str], indent: str) -> list[Line]:
    """Each row of a printed line on a line of its own, after the first where
    :func:`_continuation` puts it. Each row prints the next source line with code (a
    comment line between two rows stays between them)."""
    out: list[Line] = []
    for line in lines:
        if ROW_BREAK not in line.text:
            out.append(line)
            continue
        first, *rest = line.text.split(ROW_BREAK)
        rows = [first]
        for row in rest:
            rows.append(" " * _continuation(rows, indent, row.lstrip()) + row.lstrip())
        out.append(dataclasses.replace(line, text=first))
        origin = line.origin
        for text in rows[1:]:
            origin = next((n for n in range(origin + 1, len(source) + 1)
                           if code_of(source[n - 1]).strip()), origin + 1)
            out.append(Line(text, origin, row=True))
    return out


def _continuation(rows: list[str], indent: str, row: str) -> int:
    """The column where ``row``, the row after ``rows``, starts: a ``row`` that closes
    the innermost bracket still open under the line that opened it; else under the
    first thing inside that bracket, or, when the bracket ends its line, one ``indent``
    deeper than that line; with no bracket open, under the condition of a ``when``, or
    one ``indent`` deeper than the first row."""
    opened: list[tuple[int, int]] = []
    for number, text in enumerate(rows):
        for index, char in enumerate(code_of(text)):
            if char in "([":
                opened.append((number, index))
            elif char in ")]" and opened:
                opened.pop()
    if opened:
        number, column = opened[-1]
        text = rows[number]
        start = len(text) - len(text.lstrip())
        if row[:1] in ")]":
            return start
        return column + 1 if column < len(code_of(text).rstrip()) - 1 else start + len(indent)
    first = rows[0]
    start = len(first) - len(first.lstrip())
    return start + (len("when ") if first.lstrip().startswith("when ") else len(indent))


def with_comments(lines: list[Line], source: list[str], found: list[Comment],
                  indent: str) -> list[str]:
    """The text lines: ``lines`` with the comments ``found`` in the source. A comment on
    its own line goes before the statement that followed it (indented like it, one
    level deeper before a closing brace); one after code ends the line printed from
    that code, two spaces after it or at the author's column when the author set it
    further out (:func:`_own_column`), aligned with those of adjacent lines that the
    author aligned."""
    trailing: dict[int, list[Comment]] = {}
    leading: dict[int, list[Comment]] = {}
    for comment in found:
        owner = _owner(lines, comment.line, source) if comment.after_code else None
        if owner is None:
            index = next((i for i, line in enumerate(lines) if line.origin > comment.line),
                         len(lines))
            leading.setdefault(index, []).append(comment)
        else:
            trailing.setdefault(owner, []).append(comment)
    columns = _comment_columns(lines, trailing, source)
    out: list[str] = []
    for index in range(len(lines) + 1):
        following = next((line.text for line in lines[index:] if line.text.strip()), "")
        before = following[:len(following) - len(following.lstrip())]
        before += indent if following.strip() == "}" else ""
        out += [before + comment.text for comment in leading.get(index, [])]
        if index < len(lines):
            text = lines[index].text
            for comment in trailing.get(index, []):
                column = columns.get(comment.line, _own_column(comment, source, len(text)))
                text = text.ljust(column) + comment.text
            out.append(text)
    return _tidy(out)


def _own_column(comment: Comment, source: list[str], code: int) -> int:
    """Where a trailing comment goes after ``code`` printed columns: two spaces after
    it, or the author's column when the author set the comment :data:`SET_APART` or
    more spaces (no tab) after the code (a column chosen, often shared by comments far
    apart) and the code leaves room."""
    line = source[comment.line - 1]
    gap = line[len(line[:comment.column].rstrip()):comment.column]
    spaced = len(gap) >= SET_APART and "\t" not in gap     # a tab's width is no column
    return max(code + 2, comment.column) if spaced else code + 2


def _owner(lines: list[Line], number: int, source: list[str]) -> int | None:
    """The output line that a comment after code on source line ``number`` ends: the
    first printed from the nearest source line at or before it, or the last with code
    other than a closing brace when that source line leaves a bracket or a block open
    (the comment followed what goes on on the next line)."""
    origins = [line.origin for line in lines if 0 < line.origin <= number]
    if not origins:
        return None
    nearest = max(origins)
    printed = [i for i, line in enumerate(lines) if line.origin == nearest]
    if code_of(source[nearest - 1]).rstrip().endswith("}"):
        return printed[0]
    return next((i for i in reversed(printed) if lines[i].text.strip() != "}"), printed[0])


def _comment_columns(lines: list[Line], trailing: dict[int, list[Comment]],
                     source: list[str]) -> dict[int, int]:
    """The column of each trailing comment (by source line) that the author aligned
    with another of the same run of statements (no blank or comment line between):
    theirs, or further when the code now needs it."""
    owners = sorted((c.line, index, c) for index, group in trailing.items() for c in group)
    columns: dict[int, int] = {}
    group: list[tuple[int, int, Comment]] = []
    for owner in [*owners, None]:
        if owner is not None and group and owner[2].column == group[-1][2].column and all(
                code_of(source[n - 1]).strip() for n in range(group[-1][0] + 1, owner[0])):
            group.append(owner)
            continue
        if len(group) > 1:
            needed = max(len(lines[index].text) + 2 for _, index, _ in group)
            column = max(group[0][2].column, needed)
            columns.update({number: column for number, _, _ in group})
        group = [owner]
    return columns


def _tidy(out: list[str]) -> list[str]:
    """At most one blank line in a row, none at the ends, after a '{' or before a '}'."""
    tidy: list[str] = []
    for index, text in enumerate(out):
        if not text.strip():
            following = next((t for t in out[index + 1:] if t.strip()), None)
            if (not tidy or not tidy[-1].strip() or code_of(tidy[-1]).rstrip().endswith("{")
                    or following is None or following.strip().startswith("}")):
                continue
        tidy.append(text)
    return tidy
