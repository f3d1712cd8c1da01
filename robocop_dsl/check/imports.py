"""``import "FILE"``: read, parse and merge the declarations of imported files.

A file is looked up beside the file that imports it, then along the robots path. An
imported file holds declarations only (``let``, ``task``, ``constraint``, ``event``,
``behavior``, ``import``; a ``library`` header and a ``world``, which the importing
mission's replaces). Each file is read once however often it is imported; a cycle of
imports is an error at the import that closes it.
"""

from __future__ import annotations

import os
from functools import lru_cache
from pathlib import Path

from ..diagnostics import SourceFile, did_you_mean
from ..lang import ast, parse_mission
from ..lang.follow_on import Broken
from ..sources import MISSION, UnreadableSource, read_source
from ..world.paths import resolve
from .context import CheckContext
from .rewrite import in_file

DECLARATIONS = (ast.Let, ast.TaskDecl, ast.ConstraintDecl, ast.EventDecl, ast.BehaviorDecl)
_KEEP = "keep states, 'start' and top-level 'when' clauses in the mission that imports it"
_NOT_IN_LIBRARY = ((ast.StateDecl, "a state", _KEEP), (ast.StartDecl, "'start'", _KEEP),
                   (ast.Transition, "a top-level 'when'", _KEEP),
                   (ast.MissionHeader, "a mission header",
                    "begin a file of declarations with: library NAME \"what it holds\""),
                   (ast.ControllerDecl, "a controller",
                    "name the controller in the mission that imports it"))
_MACHINE_ITEMS = (ast.StateDecl, ast.StartDecl, ast.Transition)


def display_path(path: Path) -> str:
    """``path`` relative to the working folder when it is inside it."""
    relative = os.path.relpath(path)
    return path.as_posix() if relative.startswith("..") else relative


def merge_imports(ctx: CheckContext, mission: ast.Mission, folder: Path | None) -> ast.Mission:
    """``mission`` with the declarations of every file it imports (directly or not)
    before its own items; reports imports not found, cycles and statements that an
    imported file may not hold."""
    loader = _Loader(ctx)
    if ctx.source.path not in ("<mission>", "<stdin>"):
        loader.stack = [Path(ctx.source.path).resolve()]
    loader.import_all(mission, folder)
    own = mission.items
    if mission.first(ast.LibraryHeader) is not None:
        check_library(ctx, mission)
        own = tuple(i for i in own if not isinstance(i, _MACHINE_ITEMS))
    return ast.Mission(tuple(loader.items) + own, span=mission.span)


def check_library(ctx: CheckContext, library: ast.Mission) -> None:
    """Report what a file of declarations may not hold."""
    for item in library.items:
        for node_type, what, hint in _NOT_IN_LIBRARY:
            if isinstance(item, node_type):
                ctx.error("not-in-library", f"{what} in a library: an imported file holds "
                          "declarations only", item.span, hint)


def _near(name: str, folder: Path | None) -> str | None:
    """"did you mean" among the mission files beside the one named."""
    where = (folder / name).parent if folder is not None else None
    try:
        if where is None or not where.is_dir():
            return None
        found = [p.name for p in where.glob("*.mission")]
    except OSError:         # a name the system refuses (too long, ...)
        return None
    prefix = name.rpartition("/")[0]
    candidates = [f"{prefix}/{file}" if prefix else file for file in found]
    return did_you_mean(name, candidates)


class _Loader:
    def __init__(self, ctx: CheckContext):
        self.ctx = ctx
        self.items: list = []
        self.loaded: set[Path] = set()
        self.stack: list[Path] = []

    def import_all(self, tree: ast.Mission, folder: Path | None) -> None:
        for item in tree.of_type(ast.Import):
            self.load(item, folder)

    def load(self, item: ast.Import, folder: Path | None) -> None:
        ctx, name = self.ctx, item.path.text
        try:
            path = resolve(name, folder) if name else None
            found = path is not None and path.is_file()
        except (OSError, ValueError) as error:
            ctx.error("import-not-found", f"cannot read imported file '{name}': "
                      f"{getattr(error, 'strerror', None) or error}", item.path.span)
            return
        if not found:
            ctx.error("import-not-found", f"imported file '{name}' not found", item.path.span,
                      _near(name, folder) or "looked beside the importing file, in the "
                      "package's robots/ and in ROBOCOP_PATH folders")
            return
        path = path.resolve()
        if path in self.stack:
            chain = " -> ".join(p.name for p in self.stack[self.stack.index(path):] + [path])
            ctx.error("import-cycle", f"import cycle: {chain}", item.path.span,
                      "move the shared declarations to a file both can import")
            return
        if path in self.loaded:
            return
        self.loaded.add(path)
        tree = self._parse(item, path)
        if tree is None:
            return
        self.stack.append(path)
        self.import_all(tree, path.parent)
        self.stack.pop()
        check_library(ctx, tree)
        self.items += [i for i in tree.items if isinstance(i, DECLARATIONS)]

    def _parse(self, item: ast.Import, path: Path) -> ast.Mission | None:
        shown = display_path(path)
        try:
            text = read_source(path, MISSION).text
        except UnreadableSource as error:
            self.ctx.error("import-not-found", f"cannot read imported file '{item.path.text}': "
                           f"{error.reason}", item.path.span)
            return None
        tree, diagnostics = parsed_library(text, shown)
        self.ctx.sources[shown] = SourceFile(shown, text)
        self.ctx.diagnostics += diagnostics
        if diagnostics:
            self.ctx.broken[shown] = Broken.of(self.ctx.sources[shown], diagnostics, tree)
        self.ctx.imports_parsed = self.ctx.imports_parsed and not diagnostics
        return tree


@lru_cache(maxsize=32)
def parsed_library(text: str, shown: str) -> tuple[ast.Mission, tuple]:
    """The tree of an imported file (its spans naming it) and its syntax diagnostics;
    a file imported by many missions checked together is parsed once."""
    parsed = parse_mission(text, shown)
    return in_file(parsed.mission, shown), tuple(parsed.diagnostics)
