"""Between the checker's places (1-based lines and columns, end exclusive) and the
protocol's (0-based), and between file paths and URIs."""

from __future__ import annotations

from pathlib import Path

from lsprotocol import types
from pygls.uris import from_fs_path, to_fs_path

from ..diagnostics import Span


def to_range(span: Span | None) -> types.Range:
    """The protocol range of ``span``; the start of the file when there is none."""
    if span is None or span.line <= 0:
        return types.Range(types.Position(0, 0), types.Position(0, 0))
    return types.Range(types.Position(span.line - 1, max(span.column - 1, 0)),
                       types.Position(span.end_line - 1, max(span.end_column - 1, 0)))


def location(path: Path, span: Span | None) -> types.Location:
    return types.Location(uri=path_to_uri(path), range=to_range(span))


def path_to_uri(path: Path) -> str:
    return from_fs_path(str(path))


def uri_to_path(uri: str) -> Path:
    return Path(to_fs_path(uri) or uri).resolve()


def one_based(position: types.Position) -> tuple[int, int]:
    """``(line, column)`` of a protocol position, 1-based."""
    return position.line + 1, position.character + 1


def file_line(where: str) -> tuple[Path, Span] | None:
    """``FILE:LINE`` (as the world loader records where a body or joint is written) as
    a path and the span of that line's start."""
    path, _, line = where.rpartition(":")
    if not path or not line.isdigit():
        return None
    return Path(path), Span.point(int(line))
