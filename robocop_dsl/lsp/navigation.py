"""Go to definition, find references and rename: a name as written resolves to the
declaration it means (in this file, a file it imports, or the world's YAML or URDF),
the same way the checker reads it."""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass, field
from pathlib import Path

from lsprotocol import types
from pygls.exceptions import JsonRpcInvalidParams

from ..diagnostics import Span
from ..lang import ast
from ..lang.parser import mission_grammar
from ..lang.syntax_errors import RESERVED
from . import names
from .positions import file_line, location, to_range, uri_to_path
from .project import Parsed, Project

# What the world declares.
BODY = "body"
JOINT_GROUP = "joint group"
JOINT = "joint"
CONTROLLER = "controller"

RENAMABLE = (names.TASK, names.CONSTRAINT, names.STATE, names.FINAL, names.BEHAVIOR,
             names.CONSTANT, names.EVENT, names.PARAM, names.REGION, names.VAR)
LOCAL = (names.STATE, names.FINAL, names.PARAM, names.REGION, names.VAR)
"""What only its own file can name."""
_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_TOP = {ast.TaskDecl: names.TASK, ast.ConstraintDecl: names.CONSTRAINT,
        ast.EventDecl: names.EVENT, ast.BehaviorDecl: names.BEHAVIOR, ast.Let: names.CONSTANT}
_LOOKUP = {
    names.CONTROLLED: (names.PARAM, names.TASK, names.CONSTRAINT),
    names.OWNER: (names.PARAM, names.STATE, names.TASK, names.CONSTRAINT, BODY),
    names.STATE: (names.STATE,),
    names.EVENT: (names.PARAM, names.EVENT),
    names.BEHAVIOR: (names.BEHAVIOR,),
    names.VALUE: (names.PARAM, names.CONSTANT, names.TASK, names.CONSTRAINT, names.EVENT,
                  BODY, JOINT_GROUP, JOINT),
    names.BODY: (names.PARAM, names.CONSTANT, BODY),
    names.SET: (names.PARAM, names.CONSTANT, BODY, JOINT_GROUP),
    names.READ: (names.PARAM, names.VAR, names.CONSTANT),
    names.ASSIGNED: (names.VAR,),
    names.SUBJECT: (BODY, JOINT_GROUP, JOINT),
    names.CONTROLLER: (CONTROLLER,),
}


@dataclass(frozen=True)
class Target:
    """What a name resolves to: its kind, the file and span of the declaring name (or
    the world file's line), and the declaration node when it is in a mission."""

    kind: str
    name: str
    path: Path
    span: Span
    node: object = field(default=None, compare=False)

    @property
    def key(self) -> tuple:
        return self.path, self.span.line, self.span.column

    def location(self) -> types.Location:
        return location(self.path, self.span)


def top_level(project: Project, parsed: Parsed) -> dict[tuple[str, str], Target]:
    """Declarations of ``parsed`` and the files it imports, by (kind, name): the
    file's own first, then its imports'."""
    table: dict[tuple[str, str], Target] = {}
    for source in project.closure(parsed.path):
        for item in source.tree.items:
            kind = _TOP.get(type(item))
            if kind is not None:
                table.setdefault((kind, item.name.text),
                                 Target(kind, item.name.text, source.path, item.name.span, item))
    return table


def _state(parsed: Parsed, occurrence: names.Occurrence, name: str) -> Target | None:
    """The state ``name`` seen from ``occurrence``: in the innermost machine around it
    that has one, else anywhere in the same behaviour or mission."""
    for machine in occurrence.machines:
        for state in machine.states:
            if state.name.text == name:
                return _state_target(parsed, state)
    for other in parsed.occurrences:
        if other.declares and other.role in (names.STATE, names.FINAL) and other.text == name \
                and other.behavior is occurrence.behavior:
            return Target(other.role, name, parsed.path, other.name.span)
    return None


def variable(parsed: Parsed, occurrence: names.Occurrence, name: str) -> Target | None:
    """The var ``name`` seen from ``occurrence``: declared in a machine around it,
    innermost first, else at the top of the file (every behaviour sees those)."""
    for machine in (*occurrence.machines, parsed.tree.machine):
        for decl in machine.variables:
            if decl.name.text == name:
                return Target(names.VAR, name, parsed.path, decl.name.span, decl)
    return None


def _state_target(parsed: Parsed, state: ast.StateDecl) -> Target:
    kind = names.FINAL if state.final else names.STATE
    return Target(kind, state.name.text, parsed.path, state.name.span, state)


def _world_target(project: Project, parsed: Parsed, kind: str, name: str) -> Target | None:
    world = project.world(parsed.path)
    if world is None:
        return None
    description = project.worlds.description(world.path)
    if kind == BODY and world.has_body(name):
        where = file_line(world.body(name).where)
        return Target(BODY, name, *where) if where else None
    if kind == JOINT_GROUP and description is not None and name in description.groups:
        at = description.groups[name].at
        return Target(JOINT_GROUP, name, Path(at.source.path), at.span)
    if kind == JOINT and name in world.joint_names():
        where = file_line(world.joint(name).where)
        return Target(JOINT, name, *where) if where else None
    if kind == CONTROLLER and description is not None and name in description.processors:
        at = description.processors[name].at
        return Target(CONTROLLER, name, Path(at.source.path), at.span)
    return None


def _machines_in(path: Path, state: ast.StateDecl, behaviors: dict) -> list[tuple]:
    """The machines inside a state, with their files: its regions', or its
    behaviour's."""
    machines = [(path, r.machine) for r in state.regions if r.machine is not None]
    if state.instance is not None:
        behavior = behaviors.get((names.BEHAVIOR, state.instance.behavior.text))
        if behavior is not None:
            machines.append((behavior.path, behavior.node.machine))
    return machines


def _member(project: Project, parsed: Parsed, occurrence: names.Occurrence) -> Target | None:
    """A final or region named after a state's dot: ``pick.arrived``, ``both.left``."""
    owner = _state(parsed, occurrence, occurrence.context)
    if owner is None or not isinstance(owner.node, ast.StateDecl):
        return None
    if occurrence.role == names.REGION:
        region = next((r for r in owner.node.regions if r.name is not None
                       and r.name.text == occurrence.text), None)
        return Target(names.REGION, region.name.text, parsed.path, region.name.span) \
            if region else None
    for path, machine in _machines_in(parsed.path, owner.node, top_level(project, parsed)):
        for state in machine.states:
            if state.final and state.name.text == occurrence.text:
                return Target(names.FINAL, state.name.text, path, state.name.span, state)
    return None


def resolve(project: Project, parsed: Parsed, occurrence: names.Occurrence,
            table: dict | None = None, world: bool = True) -> Target | None:
    """The declaration that ``occurrence`` declares or names, ``None`` when unknown;
    ``table`` is :func:`top_level` of ``parsed`` when known, and without ``world`` the
    world's bodies, joints and controllers are not looked up."""
    if occurrence.declares:
        return Target(occurrence.role, occurrence.text, parsed.path, occurrence.name.span,
                      occurrence.node)
    if occurrence.role == names.ARGUMENT:
        behavior = top_level(project, parsed).get((names.BEHAVIOR, occurrence.context))
        parameter = next((p for p in behavior.node.parameters
                          if p.name.text == occurrence.text), None) if behavior else None
        return Target(names.PARAM, parameter.name.text, behavior.path, parameter.name.span) \
            if parameter else None
    if occurrence.role in (names.FIELD, names.REGION):
        return _member(project, parsed, occurrence)
    for kind in _LOOKUP.get(occurrence.role, ()):
        if kind == names.PARAM and occurrence.behavior is not None:
            parameter = next((p for p in occurrence.behavior.parameters
                              if p.name.text == occurrence.text), None)
            if parameter is not None:
                return Target(names.PARAM, occurrence.text, parsed.path, parameter.name.span)
        elif kind == names.STATE:
            found = _state(parsed, occurrence, occurrence.text)
            if found is not None:
                return found
        elif kind == names.VAR:
            found = variable(parsed, occurrence, occurrence.text)
            if found is not None:
                return found
        elif kind in (BODY, JOINT_GROUP, JOINT, CONTROLLER):
            found = _world_target(project, parsed, kind, occurrence.text) if world else None
            if found is not None:
                return found
        elif kind != names.PARAM:
            table = table if table is not None else top_level(project, parsed)
            if (kind, occurrence.text) in table:
                return table[(kind, occurrence.text)]
    return None


def target_at(project: Project, path: Path, line: int, column: int):
    """The parsed file, the name at a 1-based position and what it resolves to."""
    parsed = project.parsed(path)
    occurrence = names.at(parsed.occurrences, line, column) if parsed else None
    if occurrence is None:
        return parsed, None, None
    return parsed, occurrence, resolve(project, parsed, occurrence)


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


def references(project: Project, target: Target, include_declaration: bool = True
               ) -> list[types.Location]:
    """Every place that names ``target``, in the files that can see it (for what the
    world declares, the missions on that world)."""
    local = target.kind in LOCAL
    imported = not local and target.kind not in (BODY, JOINT_GROUP, JOINT, CONTROLLER)
    found = []
    for path in ([target.path] if local else project.files()):
        parsed = project.parsed(path)
        if parsed is None or (imported and target.path not in
                              [p.path for p in project.closure(path)]):
            continue
        for occurrence in parsed.occurrences:
            if occurrence.text != target.name:
                continue
            if occurrence.declares and not include_declaration:
                continue
            resolved = resolve(project, parsed, occurrence)
            if resolved is not None and resolved.key == target.key:
                found.append(location(path, occurrence.name.span))
    return found


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


def _clashes(parsed: Parsed, target: Target, other: names.Occurrence) -> bool:
    """Whether the declaration ``other`` clashes with ``target`` given its name: for a
    var, a var, parameter or state where both are seen; else any var."""
    if target.kind != names.VAR:
        return other.role == names.VAR
    declared = next((o for o in parsed.occurrences if o.declares and o.node is target.node),
                    None)
    return (declared is not None and other.role in (names.VAR, names.PARAM, names.STATE,
                                                    names.FINAL)
            and _shared(declared, other))


def _taken(project: Project, target: Target, new_name: str, paths) -> str | None:
    """What already has ``new_name`` where the renamed var, constant, task or
    constraint is named: a constant, task or constraint, or what :func:`_clashes`
    finds; ``None`` when the name is free."""
    for path in paths:
        parsed = project.parsed(path)
        if parsed is None:
            continue
        table = top_level(project, parsed)
        for kind in (names.CONSTANT, names.TASK, names.CONSTRAINT):
            if (kind, new_name) in table:
                other = table[(kind, new_name)]
                return f"the {kind} declared at {other.path.name}:{other.span.line}"
        for other in parsed.occurrences:
            if other.declares and other.text == new_name and _clashes(parsed, target, other):
                return f"the {other.role} declared at {path.name}:{other.name.span.line}"
    return None


def rename(project: Project, path: Path, line: int, column: int,
           new_name: str) -> types.WorkspaceEdit | None:
    """Edits renaming the declaration under the position everywhere it is named;
    refused (an error for the client) when ``new_name`` is no name or is taken."""
    _, _, target = target_at(project, path, line, column)
    if target is None or target.kind not in RENAMABLE:
        return None
    if not _IDENTIFIER.match(new_name) or new_name in keywords():
        raise JsonRpcInvalidParams(f"'{new_name}' is not a name: letters, digits and _, "
                                   "not starting with a digit, not a keyword")
    found = references(project, target)
    changes: dict[str, list[types.TextEdit]] = {}
    for place in found:
        changes.setdefault(place.uri, []).append(types.TextEdit(place.range, new_name))
    if target.kind in (names.VAR, names.CONSTANT, names.TASK, names.CONSTRAINT) \
            and new_name != target.name:
        paths = dict.fromkeys(uri_to_path(p.uri) for p in found)
        taken = _taken(project, target, new_name, paths)
        if taken is not None:
            raise JsonRpcInvalidParams(f"cannot rename '{target.name}' to '{new_name}': "
                                       f"'{new_name}' is already {taken}")
    return types.WorkspaceEdit(changes=changes)


def prepare_rename(project: Project, path: Path, line: int, column: int):
    """The range of a renamable name under the position, else ``None``."""
    parsed, occurrence, target = target_at(project, path, line, column)
    if target is None or target.kind not in RENAMABLE:
        return None
    return to_range(occurrence.name.span)
