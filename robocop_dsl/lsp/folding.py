"""Folding: every block (``{ ... }``) and vector (``[ ... ]``) written over several
lines, runs of comment lines and of ``import`` lines."""

from __future__ import annotations

from lsprotocol import types

from ..lang.syntax_errors import code_of

Kind = types.FoldingRangeKind


def _runs(lines: list[str], test, kind) -> list[types.FoldingRange]:
    """A range for each run of two lines or more for which ``test`` holds."""
    found, start = [], None
    for number, line in enumerate([*lines, ""]):
        if test(line):
            start = number if start is None else start
            continue
        if start is not None and number - 1 > start:
            found.append(types.FoldingRange(start, number - 1, kind=kind))
        start = None
    return found


def folding_ranges(text: str) -> list[types.FoldingRange]:
    """The folding ranges of a mission's text (0-based lines); a block folds up to the
    line before its ``}`` when that ``}`` starts its line."""
    lines = text.split("\n")
    found: list[types.FoldingRange] = []
    opened: list[int] = []
    for number, line in enumerate(lines):
        code = code_of(line)
        for index, char in enumerate(code):
            if char in "{[":
                opened.append(number)
            elif char in "}]" and opened:
                start = opened.pop()
                end = number - 1 if not code[:index].strip() else number
                if end > start:
                    found.append(types.FoldingRange(start, end))
    found += _runs(lines, lambda line: line.lstrip().startswith("#"), Kind.Comment)
    found += _runs(lines, lambda line: line.lstrip().startswith("import "), Kind.Imports)
    return sorted(found, key=lambda r: (r.start_line, r.end_line))
