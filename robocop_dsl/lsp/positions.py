"""Places between the checker and the editor, and between file paths and URIs.

Inside the server a place is a :class:`~robocop_dsl.diagnostics.Span` (1-based lines,
columns counted in characters, end exclusive) or a protocol range with 0-based lines
and character columns, as :func:`to_range` builds it. On the wire a column counts code
units of the encoding the client and the server agreed on at initialization (UTF-8,
UTF-16 or UTF-32): :class:`Encoding` converts both ways with the text of the file the
place is in, and refuses a request's position that is not in its document.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Callable
from urllib.parse import quote, unquote

from lsprotocol import types
from pygls.exceptions import JsonRpcInvalidParams
from pygls.uris import from_fs_path, to_fs_path
from pygls.workspace.position_codec import Utf16, impls

from ..diagnostics import SourceFile, Span


def to_range(span: Span | None) -> types.Range:
    """The range of ``span`` in characters; the start of the file when there is none."""
    if span is None or span.line <= 0:
        return types.Range(types.Position(0, 0), types.Position(0, 0))
    return types.Range(types.Position(span.line - 1, max(span.column - 1, 0)),
                       types.Position(span.end_line - 1, max(span.end_column - 1, 0)))


def location(path: Path, span: Span | None) -> types.Location:
    return types.Location(uri=path_to_uri(path), range=to_range(span))


UNSAVED = Path(os.devnull, "unsaved")
"""Where a document that is no file (``untitled:Untitled-1``, a new unsaved one) is
kept: under a device, a folder that cannot exist, so that nothing resolves beside it
(its relative imports are not found; its world is looked up along the robots path)."""


class Spellings:
    """The names the client gives files. Inside the server a file is its resolved path
    (one file, one key, whatever links lead to it); what goes back to the client names
    it as the client does: an open document by the URI it was opened with (so is a
    document that is no file, closed or not), a file under a workspace folder under
    that folder's own path (a folder reached through a symbolic link keeps the link's
    name)."""

    def __init__(self):
        self._open: dict[Path, str] = {}
        self._folders: list[tuple[Path, Path]] = []

    def opened(self, uri: str) -> Path:
        """Remember the URI of an open document; its resolved path."""
        path = uri_to_path(uri)
        self._open[path] = uri
        return path

    def closed(self, path: Path) -> None:
        self._open.pop(path, None)

    def folders(self, uris: list[str]) -> list[Path]:
        """Remember the workspace folders' URIs; their resolved paths."""
        self._folders = [(uri_to_path(uri), Path(to_fs_path(uri) or uri)) for uri in uris]
        return [resolved for resolved, _ in self._folders]

    def uri(self, path: Path) -> str:
        if path in self._open:
            return self._open[path]
        if path.parent == UNSAVED:
            return unquote(path.name)
        for resolved, spelled in self._folders:
            if resolved != spelled and path.is_relative_to(resolved):
                return from_fs_path(str(spelled / path.relative_to(resolved)))
        return from_fs_path(str(path))


SPELLINGS = Spellings()
"""The client's names of the files of this server's process (one client per server)."""


def path_to_uri(path: Path) -> str:
    return SPELLINGS.uri(path)


def uri_to_path(uri: str) -> Path:
    """The resolved path of a ``file:`` URI; for any other URI, its name under
    :data:`UNSAVED`."""
    return Path(to_fs_path(uri) or UNSAVED / quote(uri, safe=":")).resolve()


def file_line(where: str) -> tuple[Path, Span] | None:
    """``FILE:LINE`` (as the world loader records where a body or joint is written) as
    a path and the span of that line's start."""
    path, _, line = where.rpartition(":")
    if not path or not line.isdigit():
        return None
    return Path(path), Span.point(int(line))


def unknown_document(path: Path) -> str:
    """Why a request about ``path`` is refused (a document that is no file named by its
    URI)."""
    shown = SPELLINGS.uri(path) if path.parent == UNSAVED else path
    return f"unknown document {shown}: it is neither open nor a mission file that can be read"


class Encoding:
    """Columns in characters to and from the agreed encoding's code units. ``source``
    gives the current text of a file (``None`` when it cannot be read); lines are those
    of that text."""

    def __init__(self, encoding: str | None, source: Callable[[Path], SourceFile | None]):
        self.units = impls.get(encoding, Utf16())
        self.identity = self.units.num_units("\U0001F916") == 1
        self._read = source
        self._sources: dict[Path, SourceFile | None] = {}

    def source(self, path: Path) -> SourceFile | None:
        """The text of ``path``, read once for this conversion."""
        if path not in self._sources:
            self._sources[path] = self._read(path)
        return self._sources[path]

    # ---- out: the server's places to the client's ----
    def position(self, path: Path, position: types.Position) -> types.Position:
        """``position`` (a character column) in code units of the file's line."""
        if self.identity or position.character == 0:
            return position
        line = self._line(path, position.line)
        if line.isascii():
            return position
        return types.Position(position.line, self.units.num_units(line[:position.character]))

    def range(self, path: Path, range_: types.Range) -> types.Range:
        return types.Range(self.position(path, range_.start), self.position(path, range_.end))

    def location(self, found: types.Location) -> types.Location:
        return types.Location(found.uri, self.range(uri_to_path(found.uri), found.range))

    def edit(self, path: Path, edit: types.TextEdit) -> types.TextEdit:
        return types.TextEdit(self.range(path, edit.range), edit.new_text)

    def workspace_edit(self, changes: types.WorkspaceEdit) -> types.WorkspaceEdit:
        return types.WorkspaceEdit(changes={
            uri: [self.edit(uri_to_path(uri), e) for e in edits]
            for uri, edits in (changes.changes or {}).items()})

    def diagnostic(self, path: Path, found: types.Diagnostic) -> types.Diagnostic:
        """``found``, a diagnostic of ``path``, with its places in code units."""
        found.range = self.range(path, found.range)
        for related in found.related_information or []:
            related.location = self.location(related.location)
        return found

    def column(self, path: Path, line: int, column: int) -> int:
        """The 0-based character ``column`` of 0-based ``line`` in code units."""
        return self.position(path, types.Position(line, column)).character

    # ---- in: a request's position to the server's ----
    def decode(self, path: Path, position: types.Position) -> tuple[int, int]:
        """The 0-based line and character column of a request's position; a column past
        the end of its line stands for the end of the line. Raises
        :class:`~pygls.exceptions.JsonRpcInvalidParams` when the document is unknown or
        the line is not in it."""
        source = self.source(path)
        if source is None:
            raise JsonRpcInvalidParams(unknown_document(path))
        if position.line >= source.line_count:
            raise JsonRpcInvalidParams(
                f"line {position.line} is past the end of {path.name} (lines 0 to "
                f"{source.line_count - 1})")
        line = source.line(position.line + 1)
        if self.identity or line.isascii():
            return position.line, min(position.character, len(line))
        units = 0
        for index, char in enumerate(line):
            if units >= position.character:
                return position.line, index
            units += self.units.code_units_for_char(char)
        return position.line, len(line)

    def _line(self, path: Path, line: int) -> str:
        source = self.source(path)
        return source.line(line + 1) if source is not None else ""
