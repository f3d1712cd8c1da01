"""Worlds for the language server: each world file loaded once, and again only when one
of its files (the YAML files it includes, the URDFs it names) has changed on disk."""

from __future__ import annotations

import threading
from pathlib import Path
from typing import Callable

from ..compile import WorldCache
from ..world import World
from ..world.description import WorldDescription, read_description


def _files(description: WorldDescription) -> set[Path]:
    """Every file a world description was read from."""
    located = [m.at for m in description.models] + [g.at for g in description.groups.values()]
    located += [p.at for p in description.processors.values()]
    files = {Path(at.source.path) for at in located} | {Path(m.urdf) for m in description.models}
    files |= {Path(d.file) for d in description.diagnostics}
    return files | {description.path}


def _stamp(files: set[Path]) -> tuple:
    """The modification times [ns] of ``files`` (``None`` for a missing one)."""
    stamps = []
    for path in sorted(files):
        try:
            stamps.append((path, path.stat().st_mtime_ns))
        except OSError:
            stamps.append((path, None))
    return tuple(stamps)


class WorldStore:
    """Loaded worlds by resolved path, checked against their files' times on each use;
    ``on_load`` is told of every (re)load. Accepted wherever the checker takes a
    :class:`~robocop_dsl.compile.WorldCache`. The checking thread and request threads
    share it: a world is loaded by one of them at a time."""

    def __init__(self, on_load: Callable[[Path], None] | None = None):
        self.on_load = on_load
        self._caches: dict[Path, WorldCache] = {}
        self._descriptions: dict[Path, WorldDescription] = {}
        self._stamps: dict[Path, tuple] = {}
        self._lock = threading.Lock()

    def load(self, path: Path):
        """The world at ``path`` and the diagnostics of loading it."""
        with self._lock:
            return self._load(Path(path))

    def _load(self, path: Path):
        description = self._descriptions.get(path)
        if description is None or _stamp(_files(description)) != self._stamps[path]:
            description = read_description(path)
            self._descriptions[path] = description
            self._stamps[path] = _stamp(_files(description))
            self._caches[path] = WorldCache()
            if self.on_load is not None:
                self.on_load(path)
        return self._caches[path].load(path)

    def description(self, path: Path) -> WorldDescription | None:
        """The description of a world already loaded (where its groups, processors and
        models are written)."""
        return self._descriptions.get(Path(path))

    def world(self, path: Path) -> World | None:
        return self.load(path)[0]
