"""Checking a mission as ``robocop-mission check`` does, on the server's own parse of
it: the world through the server's store, the files it imports as the editor has them
(an open document's unsaved text, else the disk), and no compilation. A check that
the text has outrun stops at the next boundary between the checker's passes."""

from __future__ import annotations

import contextlib
import threading
from pathlib import Path
from typing import Callable

from ..compile import build_state_graph  # first: it imports the checker
from ..compile.load import _world_of, gathered
from ..check import Cancelled, check_graph, check_mission  # noqa: I001
from ..check import imports as checked_imports
from ..diagnostics import Diagnostic, SourceFile
from ..sources import read_source
from .project import COLLECTOR, Parsed, Project

_READER = threading.Lock()


@contextlib.contextmanager
def unsaved_imports(texts: dict[Path, str]):
    """While the block runs, the checker reads an imported file from ``texts`` (the
    open documents) when it is there: it reads them through its module's
    ``read_source``, which this replaces for that time (one check at a time)."""
    def read(path, kind=None) -> SourceFile:
        text = texts.get(Path(path).resolve())
        return SourceFile(str(path), text) if text is not None else read_source(path, kind)

    with _READER:
        checked_imports.read_source = read
        try:
            yield
        finally:
            checked_imports.read_source = read_source


def check(project: Project, parsed: Parsed, stale: Callable[[], bool] = lambda: False,
          texts: dict[Path, str] | None = None) -> list[Diagnostic] | None:
    """Every diagnostic of the mission ``parsed``, sorted as ``check`` sorts them;
    ``None`` when ``stale()`` says the text changed before the check was over (asked
    between the checker's passes). Imported files are read from ``texts`` when there
    (by default the open documents), else from the disk."""
    source, tree = parsed.result.source, parsed.tree
    texts = dict(project.open) if texts is None else texts
    with COLLECTOR.paused(), unsaved_imports(texts):
        _, world, loading = _world_of(tree, source, project.worlds)
        if stale():
            return None
        try:
            ctx = check_mission(tree, source, world, parsed.path.parent, stale)
            if stale():
                return None
            if parsed.result.ok:
                check_graph(ctx, ctx.expanded, build_state_graph(ctx.expanded), stale)
        except Cancelled:
            return None
    return gathered(parsed.result, loading, ctx)
