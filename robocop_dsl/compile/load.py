"""From a mission file to diagnostics or a compiled mission: parse, load the world,
check, build the state graph, check it, compile."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import networkx as nx

from ..check import check_graph, check_mission
from ..check.context import CheckContext
from ..diagnostics import Diagnostic, DiagnosticError, SourceFile, sort_key, unique
from ..lang import ast, parse_mission
from ..lang.follow_on import Broken
from ..lang.parser import ParseResult
from ..sources import MISSION, WORLD, UnreadableSource, read_source, refusal
from ..world import World, load_world, resolve_world_path
from .state_graph import build_state_graph

if TYPE_CHECKING:
    from .spec import MissionSpec


@dataclass(frozen=True)
class CheckResult:
    """Everything ``check`` learnt about one mission file.

    ``world`` is ``None`` when the mission names none or it failed to load; ``mission``
    is the compiled mission when there is no error and it was asked for, else ``None``.
    """

    source: SourceFile
    diagnostics: tuple[Diagnostic, ...]
    syntax_tree: ast.Mission
    graph: nx.DiGraph
    world: World | None
    mission: MissionSpec | None

    @property
    def ok(self) -> bool:
        return not any(d.is_error for d in self.diagnostics)

    @property
    def warnings(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if not d.is_error]


class WorldCache:
    """Worlds loaded so far, by resolved path: checking many missions loads each once."""

    def __init__(self):
        self._worlds: dict[Path, tuple[World | None, tuple[Diagnostic, ...]]] = {}

    def load(self, path: Path) -> tuple[World | None, tuple[Diagnostic, ...]]:
        """The world at ``path`` or ``None``, and the diagnostics of loading it; a
        system error (a name too long for the file system) is a diagnostic at 1:1."""
        if path not in self._worlds:
            try:
                self._worlds[path] = (load_world(path), ())
            except DiagnosticError as error:
                self._worlds[path] = (None, tuple(error.diagnostics))
            except OSError as error:
                self._worlds[path] = (None, (UnreadableSource(
                    str(path), error.strerror or str(error)).diagnostics[0],))
        return self._worlds[path]


def _world_of(mission: ast.Mission, source: SourceFile, cache: WorldCache):
    """The resolved world path, the world (or ``None``) and diagnostics about loading it."""
    declared = mission.first(ast.WorldDecl)
    if declared is None:
        return None, None, []
    folder = Path(source.path).parent if source.path != "<stdin>" else Path.cwd()
    try:
        path = resolve_world_path(declared.path.text, relative_to=folder.resolve())
    except (OSError, ValueError) as error:
        return None, None, [source.error(
            "unreadable-file", f"cannot read world file '{declared.path.text}': "
            f"{getattr(error, 'strerror', None) or error}", declared.path.span)]
    if path is None:
        return None, None, [source.error(
            "world-not-found", f"world file '{declared.path.text}' not found",
            declared.path.span, "looked beside the mission, in the package's robots/ and "
            "in ROBOCOP_PATH folders")]
    refused = refusal(path, WORLD)
    if refused is not None:
        return None, None, [source.error(
            "unreadable-file", f"cannot read world file '{declared.path.text}': {refused}",
            declared.path.span, "a mission names a world file (.yaml or .yml)")]
    world, problems = cache.load(path)
    if world is None:
        return path, None, [source.error(
            "world-error", f"the world '{declared.path.text}' has errors",
            declared.path.span, "see the errors reported in the world file"), *problems]
    return path, world, []


def check_source(text: str, path: str | Path = "<mission>", *, world: World | None = None,
                 cache: WorldCache | None = None, compiled: bool = True) -> CheckResult:
    """Parse and check mission ``text``; compile it when there is no error, unless
    ``compiled`` is false (the diagnostics alone are wanted: the compiler and its specs
    are not even imported).

    ``world``, when given, is used instead of the one the mission names (tests and
    tools that check many texts against one world). Never raises on bad input.
    """
    parsed = parse_mission(text, path)
    source, tree = parsed.source, parsed.mission
    if world is not None:
        world_path, loading = Path(world.path), []
    else:
        world_path, world, loading = _world_of(tree, source, cache or WorldCache())
    folder = Path(source.path).parent.resolve() if source.path not in ("<mission>", "<stdin>") \
        else Path.cwd()
    ctx = check_mission(tree, source, world, folder)
    graph = build_state_graph(ctx.expanded)
    if parsed.ok:
        check_graph(ctx, ctx.expanded, graph)
    diagnostics = tuple(gathered(parsed, loading, ctx))
    mission = None
    if compiled and not any(d.is_error for d in diagnostics) and world is not None \
            and tree.first(ast.MissionHeader) is not None:
        from .compiler import compile_mission

        mission = compile_mission(ctx.expanded, source, world, world_path, graph)
    return CheckResult(source, diagnostics, tree, graph, world, mission)


def gathered(parsed: ParseResult, loading: Iterable[Diagnostic], ctx: CheckContext
             ) -> list[Diagnostic]:
    """The parse's diagnostics, those of loading the world and the checker's, without
    repeats and without what only follows from a statement that did not parse, in this
    file or one it imports (:class:`~robocop_dsl.lang.follow_on.Broken`), the file's own
    first."""
    source = parsed.source
    broken = {source.path: Broken.of(source, parsed.diagnostics, parsed.mission),
              **ctx.broken}
    kept = [d for d in [*loading, *ctx.diagnostics]
            if d.file not in broken or not broken[d.file].follows(d)]
    return sorted(unique([*parsed.diagnostics, *kept]),
                  key=lambda d: (d.file != source.path, *sort_key(d)))


def check_file(path: str | Path, *, world: World | None = None,
               cache: WorldCache | None = None, compiled: bool = True) -> CheckResult:
    """Read a mission file and :func:`check_source` it (``compiled`` as there). An
    unreadable file is a diagnostic too."""
    try:
        text = read_source(path, MISSION).text
    except UnreadableSource as error:
        return CheckResult(SourceFile(str(path), ""), tuple(error.diagnostics), ast.Mission(),
                           nx.DiGraph(start=None, guards=(), machines={}), None, None)
    return check_source(text, path, world=world, cache=cache, compiled=compiled)


def load_mission(path: str | Path, *, world: World | None = None) -> MissionSpec:
    """Parse, check and compile a mission file.

    Raises :class:`~robocop_dsl.diagnostics.DiagnosticError` with every diagnostic
    (warnings included) when there is any error.
    """
    result = check_file(path, world=world)
    if result.mission is None:
        raise DiagnosticError(result.diagnostics)
    return result.mission
