"""Reading a source file (a mission, a world, a URDF): the one place that opens them.

A file is read only when it is a regular file (after following links) whose name and
target end with an extension of its kind, and is at most :data:`MAX_SOURCE_BYTES`
long. Anything else (``/etc/shadow``, ``/dev/zero``, ``/dev/stdin``, a FIFO, a key
file) is refused before a byte of it is read, so no diagnostic can ever quote it.
Text is UTF-8; a URDF may declare another encoding in its XML declaration.
"""

from __future__ import annotations

import codecs
import os
import re
import stat
from pathlib import Path

from .diagnostics import (MISSION_BREAKS, XML_BREAKS, YAML_BREAKS, Diagnostic,
                          DiagnosticError, SourceFile, Span)

MAX_SOURCE_BYTES = 8 << 20
MISSION = (".mission",)
WORLD = (".yaml", ".yml")
URDF = (".urdf", ".xml", ".srdf")
_KIND_NAMES = {MISSION: "a mission", WORLD: "a YAML", URDF: "a URDF"}
_BREAKS = {MISSION: MISSION_BREAKS, WORLD: YAML_BREAKS, URDF: XML_BREAKS}
_LONE_RETURN = re.compile(r"\r(?!\n)")
_XML_ENCODING = re.compile(rb"""^(?:\xef\xbb\xbf)?<\?xml[^>]*?encoding\s*=\s*["']([A-Za-z0-9._-]+)["']""")


class UnreadableSource(DiagnosticError):
    """A source file that is refused or cannot be read. ``reason`` says why (never the
    file's content); the one diagnostic is located in the file: at 1:1, or where the
    problem is (a byte that is not UTF-8), quoting that line only then."""

    def __init__(self, path: str, reason: str, span: Span | None = None,
                 source_line: str = ""):
        self.path, self.reason = path, reason
        super().__init__([Diagnostic("unreadable-file", f"cannot read the file: {reason}",
                                     path, span or Span.point(1), source_line=source_line)])


def editor_lines(text: str) -> str:
    """``text`` with each lone carriage return made a line feed (the length unchanged):
    a mission's lines are those an editor shows, where a ``\\r`` alone ends a line too."""
    return _LONE_RETURN.sub("\n", text) if "\r" in text else text


def kind_of(path: str | Path) -> tuple[str, ...] | None:
    """The kind (a tuple of extensions) a file name belongs to, or ``None``."""
    suffix = Path(path).suffix.lower()
    return next((kind for kind in _BREAKS if suffix in kind), None)


def not_a_file(path: str | Path) -> str | None:
    """Why ``path`` names no file to read (``no such file``, ``not a regular file``: a
    folder, a device), or ``None`` when it names one."""
    name = Path(path)
    if name.is_file():
        return None
    return "not a regular file" if name.exists() else "no such file"


def refusal(path: str | Path, kind: tuple[str, ...]) -> str | None:
    """Why ``path`` may not be read as a file of ``kind``, or ``None`` when it may.

    Only the name and ``stat`` are looked at; the file is not opened.
    """
    name = Path(path)
    expected = " or ".join(kind)
    if name.suffix.lower() not in kind:
        return f"not {_KIND_NAMES[kind]} file (the name must end with {expected})"
    return file_refusal(name, kind, expected, MAX_SOURCE_BYTES)


def file_refusal(path: Path, suffixes: tuple[str, ...], expected: str,
                 limit: int | None = None) -> str | None:
    """Why ``path`` is no regular file whose target's name ends with one of
    ``suffixes`` (``expected`` names them in the message) and of at most ``limit``
    bytes, or ``None``. Only ``stat`` is asked; the file is not opened."""
    try:
        target = path.resolve()
        info = os.stat(path)
    except (OSError, RuntimeError, ValueError) as error:
        return getattr(error, "strerror", None) or str(error)
    if target.suffix.lower() not in suffixes:
        return f"it links to a file whose name does not end with {expected}"
    if not stat.S_ISREG(info.st_mode):
        return "not a regular file"
    if limit is not None and info.st_size > limit:
        return f"larger than {limit} bytes"
    return None


def read_source(path: str | Path, kind: tuple[str, ...] | None = None) -> SourceFile:
    """The text of ``path`` as a :class:`SourceFile` whose lines are counted the way
    the kind's parser counts them; ``kind`` defaults to the one of the file's extension.

    Raises:
        UnreadableSource: the file is refused or cannot be read or decoded.
    """
    shown = str(path)
    kind = kind or kind_of(path)
    if kind is None:
        raise UnreadableSource(shown, "not a mission, YAML or URDF file (the name must end "
                               "with " + ", ".join(e for k in _BREAKS for e in k) + ")")
    reason = refusal(path, kind)
    if reason is not None:
        raise UnreadableSource(shown, reason)
    data = _read_bytes(shown)
    encoding = _encoding(data) if kind == URDF else "utf-8"
    try:
        text = data.decode(encoding)
    except UnicodeDecodeError as error:
        lines = editor_lines if kind == MISSION else str
        prefix = lines(data[:error.start].decode(encoding, errors="replace"))
        probe = SourceFile(shown, prefix, _BREAKS[kind])
        line, column = probe.position(len(prefix))
        whole = SourceFile(shown, lines(data.decode(encoding, errors="replace")),
                           _BREAKS[kind])
        raise UnreadableSource(shown, f"byte 0x{data[error.start]:02x} at offset "
                               f"{error.start} is not {encoding}", Span.point(line, column),
                               whole.line(line)) from None
    return SourceFile(shown, text.removeprefix("\ufeff"), _BREAKS[kind])


def _read_bytes(path: str) -> bytes:
    """At most :data:`MAX_SOURCE_BYTES` of a regular file, checked again once open."""
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
    try:
        descriptor = os.open(path, flags)
    except OSError as error:
        raise UnreadableSource(path, error.strerror or str(error)) from None
    with os.fdopen(descriptor, "rb") as stream:
        if not stat.S_ISREG(os.fstat(stream.fileno()).st_mode):
            raise UnreadableSource(path, "not a regular file")
        try:
            data = stream.read(MAX_SOURCE_BYTES + 1)
        except OSError as error:
            raise UnreadableSource(path, error.strerror or str(error)) from None
    if len(data) > MAX_SOURCE_BYTES:
        raise UnreadableSource(path, f"larger than {MAX_SOURCE_BYTES} bytes")
    return data


def _encoding(data: bytes) -> str:
    """The encoding an XML declaration names (UTF-8 when none or unknown)."""
    match = _XML_ENCODING.match(data)
    if match is None:
        return "utf-8"
    try:
        return codecs.lookup(match.group(1).decode("ascii")).name
    except LookupError:
        return "utf-8"
