"""Go to definition, find references, document highlights and rename.

A rename is refused, saying why (an error for the client), when the new name is no
name, is a keyword, or already names something the checker would then confuse it with
where it is seen: another task, constraint, event or constant (a var too) for those;
another behaviour; another state of the same machine; another region of the same
state; another parameter of the same behaviour; and for a var, what :func:`_clashes`
says. A rename that passes those rules is then tried on every file that sees the
declaration (:mod:`.rename_check`): one that makes an error appear is refused too."""

from __future__ import annotations

import functools
import re
from pathlib import Path

from lsprotocol import types
from pygls.exceptions import JsonRpcInvalidParams

from ..diagnostics import Span
from ..lang import ast
from ..lang.parser import mission_grammar
from ..lang.syntax_errors import RESERVED
from . import names, rename_check
from .positions import location, path_to_uri, to_range
from .project import Parsed, Project
from .resolve import LOCAL, WORLD_KINDS, Resolver, Target, top_level

RENAMABLE = (names.TASK, names.CONSTRAINT, names.STATE, names.FINAL, names.BEHAVIOR,
             names.CONSTANT, names.EVENT, names.PARAM, names.REGION, names.VAR)
_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_SHARED_NAMES = (names.TASK, names.CONSTRAINT, names.EVENT, names.CONSTANT)
_TOP_CLASHES = {**{kind: _SHARED_NAMES for kind in _SHARED_NAMES},
                names.BEHAVIOR: (names.BEHAVIOR,),
                names.VAR: (names.TASK, names.CONSTRAINT, names.CONSTANT)}


def target_at(project: Project, path: Path, line: int, column: int):
    """The parsed file, the name at a 1-based position and what it resolves to."""
    parsed = project.parsed(path)
    occurrence = names.at(parsed.occurrences, line, column) if parsed else None
    if occurrence is None:
        return parsed, None, None
    return parsed, occurrence, Resolver(project, parsed)(occurrence)


def _file_statement(project: Project, parsed: Parsed, line: int, column: int):
    """The file an ``import`` or ``world`` string under the position names."""
    for item in parsed.tree.items:
        if isinstance(item, (ast.Import, ast.WorldDecl)):
            span = item.path.span
            if span.line == line and span.column <= column <= span.end_column:
                if isinstance(item, ast.WorldDecl):
                    return project.world_path(parsed.path)
                return next((p for i, p in parsed.imports() if i is item), None)
    return None


def definition(project: Project, path: Path, line: int, column: int) -> list[types.Location]:
    parsed, _, target = target_at(project, path, line, column)
    if target is not None:
        return [target.location()]
    named = _file_statement(project, parsed, line, column) if parsed else None
    return [location(named, Span.point(1))] if named else []


def _places(project: Project, target: Target, paths) -> list[tuple[Path, names.Occurrence]]:
    """The occurrences of the files ``paths`` that name ``target``, declaration
    included."""
    found = []
    for path in paths:
        parsed = project.parsed(path)
        if parsed is None:
            continue
        resolver = Resolver(project, parsed)
        found += [(path, o) for o in parsed.occurrences
                  if o.text == target.name and (resolved := resolver(o)) is not None
                  and resolved.key == target.key]
    return found


def naming(project: Project, target: Target) -> list[tuple[Path, names.Occurrence]]:
    """Every place that names ``target``, in the files that can see it: its own and
    those that import it for a state, var, parameter or region (a behaviour's final
    states and parameters are named where it is instantiated: ``first.arrived``,
    ``height = 5 cm``); those that import its file for a declaration; for what the
    world declares, every mission and library known (open, imported or in the
    workspace)."""
    if target.kind in LOCAL:
        return _places(project, target, _seeing(project, target) or [target.path])
    paths = project.files()
    if target.kind not in WORLD_KINDS:
        paths = [p for p in paths if target.path in [c.path for c in project.closure(p)]]
    return _places(project, target, paths)


def references(project: Project, target: Target, include_declaration: bool = True
               ) -> list[types.Location]:
    """The locations that name ``target``; with ``include_declaration``, the place that
    declares it too (a world file's line for what the world declares)."""
    found = [location(path, o.name.span) for path, o in naming(project, target)
             if include_declaration or not o.declares]
    if include_declaration and target.kind in WORLD_KINDS:
        found.insert(0, target.location())
    return found


def highlights(project: Project, path: Path, line: int, column: int
               ) -> list[types.DocumentHighlight]:
    """The places of this document that name what the name at the 1-based position
    names: its declaration and assignments written, its other uses read."""
    _, _, target = target_at(project, path, line, column)
    if target is None:
        return []
    return [types.DocumentHighlight(
        to_range(o.name.span),
        types.DocumentHighlightKind.Write if o.declares or o.role == names.ASSIGNED
        else types.DocumentHighlightKind.Read)
        for _, o in _places(project, target, [path])]


@functools.cache
def keywords() -> frozenset[str]:
    """The words the parser may read as keywords: no name may be one of them."""
    spelled = {t.pattern.value for t in mission_grammar().terminals
               if t.pattern.type == "str" and _IDENTIFIER.match(t.pattern.value)}
    return RESERVED | spelled


def _top(occurrence: names.Occurrence) -> bool:
    """Whether ``occurrence`` declares a var at the top of its file (seen everywhere)."""
    return occurrence.role == names.VAR and occurrence.behavior is None \
        and len(occurrence.machines) == 1


def _shared(first: names.Occurrence, second: names.Occurrence) -> bool:
    """Whether two declarations share a place where both names are seen: one is a
    top var, or the machine of one is, or is around, the other's."""
    return (_top(first) or _top(second)
            or any(m is first.machines[0] for m in second.machines)
            or any(m is second.machines[0] for m in first.machines))


def _clashes(declared: names.Occurrence, other: names.Occurrence) -> bool:
    """Whether the declaration ``other``, once it has the same name, would be confused
    with ``declared`` (a state, final, region, parameter or var)."""
    kind = declared.role
    if other.role == names.VAR or kind == names.VAR:
        return other.role in (names.VAR, names.PARAM, names.STATE, names.FINAL) \
            and _shared(declared, other)
    if kind in (names.STATE, names.FINAL):
        return other.role in (names.STATE, names.FINAL) \
            and other.machines[0] is declared.machines[0]
    if kind == names.REGION:
        return other.role == names.REGION and other.context == declared.context \
            and other.machines[0] is declared.machines[0]
    return other.role == names.PARAM and other.behavior is declared.behavior


def _taken(project: Project, target: Target, new_name: str, paths) -> str | None:
    """What already has ``new_name`` where the renamed declaration is named, as "the
    KIND declared at FILE:LINE"; ``None`` when the name is free."""
    for path in paths:
        parsed = project.parsed(path)
        if parsed is None:
            continue
        table = top_level(project, parsed)
        for kind in _TOP_CLASHES.get(target.kind, ()):
            other = table.get((kind, new_name))
            if other is not None:
                return f"the {kind} declared at {other.path.name}:{other.span.line}"
        declared = next((o for o in parsed.occurrences if o.declares
                         and o.name.span == target.span), None) \
            if target.kind in LOCAL and path == target.path else None
        for other in parsed.occurrences:
            if not other.declares or other.text != new_name:
                continue
            if (declared is not None and _clashes(declared, other)) or (
                    target.kind in _SHARED_NAMES and other.role == names.VAR):
                return f"the {other.role} declared at {path.name}:{other.name.span.line}"
    return None


def rename(project: Project, path: Path, line: int, column: int,
           new_name: str) -> types.WorkspaceEdit | None:
    """Edits renaming the declaration under the 1-based position everywhere it is
    named; refused (an error for the client) when ``new_name`` is no name or is taken."""
    _, _, target = target_at(project, path, line, column)
    if target is None or target.kind not in RENAMABLE:
        return None
    if not _IDENTIFIER.match(new_name) or new_name in keywords():
        raise JsonRpcInvalidParams(f"'{new_name}' is not a name: letters, digits and _, "
                                   "not starting with a digit, not a keyword")
    places = naming(project, target)
    if new_name != target.name:
        taken = _taken(project, target, new_name, dict.fromkeys(p for p, _ in places))
        if taken is not None:
            raise JsonRpcInvalidParams(f"cannot rename '{target.name}' to '{new_name}': "
                                       f"'{new_name}' is already {taken}")
        made = rename_check.new_error(project, places, _seeing(project, target), new_name)
        if made is not None:
            raise JsonRpcInvalidParams(f"cannot rename '{target.name}' to '{new_name}': "
                                       f"it would make an error, {made.location()}: "
                                       f"{made.message}")
    changes: dict[str, list[types.TextEdit]] = {}
    for place, occurrence in places:
        changes.setdefault(path_to_uri(place), []).append(
            types.TextEdit(to_range(occurrence.name.span), new_name))
    return types.WorkspaceEdit(changes=changes)


def _seeing(project: Project, target: Target) -> list[Path]:
    """The mission files that see the declaration of ``target``: its own and those
    whose imports reach it."""
    return [target.path, *project.importers(target.path)] if project.is_mission(target.path) \
        else []


def prepare_rename(project: Project, path: Path, line: int, column: int):
    """The range of a renamable name under the 1-based position, else ``None``."""
    _, occurrence, target = target_at(project, path, line, column)
    if target is None or target.kind not in RENAMABLE:
        return None
    return to_range(occurrence.name.span)
