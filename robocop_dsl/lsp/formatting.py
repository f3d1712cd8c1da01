"""Formatting a whole document with the mission formatter, comments kept."""

from __future__ import annotations

from lsprotocol import types

from ..lang.formatter import format_source
from .project import Parsed


def format_document(parsed: Parsed) -> list[types.TextEdit] | None:
    """One edit replacing the text by its canonical form; ``None`` while the text has
    a syntax error (nothing is rewritten from a partial tree) or is already formatted."""
    if not parsed.result.ok:
        return None
    formatted = format_source(parsed.tree, parsed.text)
    if formatted == parsed.text:
        return []
    lines = parsed.text.split("\n")
    end = types.Position(len(lines) - 1, len(lines[-1]))
    return [types.TextEdit(types.Range(types.Position(0, 0), end), formatted)]
