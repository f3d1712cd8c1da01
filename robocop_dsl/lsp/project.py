"""What the server knows: the open documents' texts, the mission files of the
workspace, their parses and imports, and the worlds they name."""

from __future__ import annotations

import os
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

from ..compile import CheckResult, check_source
from ..lang import ParseResult, ast, parse_mission
from ..sources import MISSION, UnreadableSource, read_source
from ..world import World, resolve_world_path
from ..world.paths import resolve
from . import names
from .worlds import WorldStore

MAX_WORKSPACE_FILES = 2000


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
        if text is None:
            return None
        known = self._parsed.get(path)
        if known is None or known.text != text:
            known = Parsed(path, text, parse_mission(text, str(path)))
            self._parsed[path] = known
        return known

    def closure(self, path: Path) -> list[Parsed]:
        """``path`` and every file it imports, directly or not, each once."""
        seen: dict[Path, Parsed] = {}
        waiting = [path]
        while waiting:
            current = waiting.pop(0)
            if current in seen:
                continue
            parsed = self.parsed(current)
            if parsed is None:
                continue
            seen[current] = parsed
            waiting += [imported for _, imported in parsed.imports()]
        return list(seen.values())

    def check(self, path: Path) -> CheckResult:
        """Check the current text of ``path`` as ``robocop-mission check`` does."""
        return check_source(self.text(path) or "", str(path), cache=self.worlds)

    def world_path(self, path: Path) -> Path | None:
        """The world file a mission names (resolved), if it names one that exists."""
        parsed = self.parsed(path)
        declared = parsed.tree.first(ast.WorldDecl) if parsed else None
        if declared is None:
            return None
        return resolve_world_path(declared.path.text, relative_to=path.parent)

    def world(self, path: Path) -> World | None:
        """The world of the mission at ``path``: its own or, for an imported file
        without one, that of an open mission importing it."""
        for owner in [path, *self.importers(path)]:
            world_path = self.world_path(owner)
            if world_path is not None:
                return self.worlds.world(world_path)
        return None

    def importers(self, path: Path) -> list[Path]:
        """The known mission files whose imports reach ``path``."""
        return [other for other in self.files()
                if other != path and any(p.path == path for p in self.closure(other))]

    def files(self) -> list[Path]:
        """The open documents and the ``.mission`` files under the workspace folders."""
        found = dict.fromkeys(self.open)
        for root in self.roots:
            for folder, subfolders, files in os.walk(root):
                subfolders[:] = [s for s in subfolders
                                 if not s.startswith(".") and s != "node_modules"]
                found.update(dict.fromkeys(Path(folder, f).resolve() for f in files
                                           if f.endswith(".mission")))
                if len(found) > MAX_WORKSPACE_FILES:
                    return list(found)[:MAX_WORKSPACE_FILES]
        return list(found)
