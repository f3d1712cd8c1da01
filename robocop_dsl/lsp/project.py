"""What the server knows: the open documents' texts, the mission files of the
workspace, their parses and imports, and the worlds they name. Request threads and
the checking thread share it: a file's parse is made once, under its lock."""

from __future__ import annotations

import contextlib
import gc
import os
import threading
from collections import defaultdict
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Callable

from ..diagnostics import SourceFile
from ..lang import ParseResult, ast
from ..sources import MISSION, UnreadableSource, kind_of, read_source
from ..world import World, resolve_world_path
from ..world.paths import resolve
from . import names
from .pieces import PieceCache
from .worlds import WorldStore

MAX_WORKSPACE_FILES = 2000


class _Collector:
    """Cyclic garbage collection paused while any thread parses or checks: on a large
    mission each collection walks millions of nodes and finds little to free."""

    def __init__(self):
        self._lock = threading.Lock()
        self._busy = 0

    @contextlib.contextmanager
    def paused(self):
        with self._lock:
            self._busy += 1
            gc.disable()
        try:
            yield
        finally:
            with self._lock:
                self._busy -= 1
                if not self._busy:
                    gc.enable()


COLLECTOR = _Collector()


@dataclass(frozen=True)
class Parsed:
    """One mission file's text, parse and names."""

    path: Path
    text: str
    result: ParseResult

    @property
    def tree(self) -> ast.Mission:
        return self.result.mission

    @cached_property
    def occurrences(self) -> list[names.Occurrence]:
        return names.occurrences(self.tree, self.text)

    @cached_property
    def scopes(self) -> names.Scopes:
        return names.Scopes(self.occurrences)

    def imports(self) -> list[tuple[ast.Import, Path]]:
        """The files this one imports directly, with the statement naming each."""
        found = []
        for item in self.tree.of_type(ast.Import):
            path = resolve(item.path.text, self.path.parent) if item.path.text else None
            if path is not None and path.is_file():
                found.append((item, path.resolve()))
        return found


class Project:
    """Open documents (their unsaved text wins over the disk), the workspace's folders
    and the worlds, loaded once each."""

    def __init__(self, worlds: WorldStore | None = None):
        self.worlds = worlds or WorldStore()
        self.open: dict[Path, str] = {}
        self.roots: list[Path] = []
        self._parsed: dict[Path, Parsed] = {}
        self._pieces: dict[Path, PieceCache] = defaultdict(PieceCache)
        self._locks: dict[Path, threading.Lock] = {}
        self._locking = threading.Lock()
        self._sources: dict[Path, SourceFile] = {}

    def _lock(self, path: Path) -> threading.Lock:
        with self._locking:
            return self._locks.setdefault(path, threading.Lock())

    def text(self, path: Path) -> str | None:
        if path in self.open:
            return self.open[path]
        try:
            return read_source(path, MISSION).text
        except UnreadableSource:
            return None

    def parsed(self, path: Path) -> Parsed | None:
        """The parse of ``path``'s current text (kept while the text is unchanged)."""
        text = self.text(path)
        return None if text is None else self.parse(path, text)

    def parse(self, path: Path, text: str,
              cancelled: Callable[[], bool] = lambda: False) -> Parsed:
        """The parse of ``text`` as the content of ``path``: only the pieces that
        changed since the last parse of ``path`` are parsed again.

        Raises:
            Cancelled: ``cancelled()`` was true between two pieces.
        """
        with self._lock(path):
            known = self._parsed.get(path)
            if known is None or known.text != text:
                with COLLECTOR.paused():
                    known = Parsed(path, text, self._pieces[path].parse(text, str(path),
                                                                        cancelled))
                self._parsed[path] = known
            return known

    def forget(self, path: Path) -> None:
        """Drop what is kept of a document that was closed."""
        with self._lock(path):
            self._parsed.pop(path, None)
            self._pieces.pop(path, None)
            self._sources.pop(path, None)

    def is_mission(self, path: Path) -> bool:
        """Whether ``path`` is a mission file: an open document, whatever its name, or
        a ``.mission`` file."""
        return path in self.open or kind_of(path) == MISSION

    def source(self, path: Path) -> SourceFile | None:
        """The current text of a mission, world or URDF file, its lines counted as its
        parser counts them."""
        if not self.is_mission(path):
            try:
                return read_source(path)
            except UnreadableSource:
                return None
        text = self.text(path)
        if text is None:
            return None
        known = self._sources.get(path)
        if known is None or known.text is not text:
            known = SourceFile(str(path), text)
            self._sources[path] = known
        return known

    def closure(self, path: Path) -> list[Parsed]:
        """``path`` and every file it imports, directly or not, each once."""
        return self.closure_of(self.parsed(path))

    def closure_of(self, parsed: Parsed | None) -> list[Parsed]:
        """``parsed`` and every file it imports, directly or not, each once."""
        seen: dict[Path, Parsed] = {}
        waiting = [parsed] if parsed is not None else []
        while waiting:
            current = waiting.pop(0)
            if current.path in seen:
                continue
            seen[current.path] = current
            waiting += [p for p in (self.parsed(imported) for _, imported in current.imports())
                        if p is not None]
        return list(seen.values())

    def world_path(self, path: Path) -> Path | None:
        """The world file a mission names (resolved), if it names one that exists."""
        parsed = self.parsed(path)
        declared = parsed.tree.first(ast.WorldDecl) if parsed else None
        if declared is None:
            return None
        return resolve_world_path(declared.path.text, relative_to=path.parent)

    def world(self, path: Path) -> World | None:
        """The world of the mission at ``path``: its own or, for an imported file
        without one, that of a mission importing it."""
        for owner in [path, *self.importers(path)]:
            world_path = self.world_path(owner)
            if world_path is not None:
                return self.worlds.world(world_path)
        return None

    def importers(self, path: Path, files: list[Path] | None = None) -> list[Path]:
        """The mission files (of ``files``, by default all known) whose imports reach
        ``path``."""
        return [other for other in (self.files() if files is None else files)
                if other != path and any(p.path == path for p in self.closure(other))]

    def files(self) -> list[Path]:
        """The open documents, the files they import and the ``.mission`` files under
        the workspace folders."""
        found = dict.fromkeys(self.open)
        for path in list(self.open):
            found.update(dict.fromkeys(p.path for p in self.closure(path)))
        for root in self.roots:
            for folder, subfolders, files in os.walk(root):
                subfolders[:] = [s for s in subfolders
                                 if not s.startswith(".") and s != "node_modules"]
                found.update(dict.fromkeys(Path(folder, f).resolve() for f in files
                                           if f.endswith(".mission")))
                if len(found) > MAX_WORKSPACE_FILES:
                    return list(found)[:MAX_WORKSPACE_FILES]
        return list(found)
