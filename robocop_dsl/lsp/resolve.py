"""What a name means: a name as written resolves to the declaration it names (in its
file, a file it imports, or the world's YAML or URDF), the same way the checker reads
it."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

from lsprotocol import types

from ..diagnostics import Span
from ..lang import ast
from . import names
from .positions import file_line, location
from .project import Parsed, Project

# What the world declares.
BODY = "body"
JOINT_GROUP = "joint group"
JOINT = "joint"
CONTROLLER = "controller"
WORLD_KINDS = (BODY, JOINT_GROUP, JOINT, CONTROLLER)

LOCAL = (names.STATE, names.FINAL, names.PARAM, names.REGION, names.VAR)
"""What only its own file can name."""
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
    for source in project.closure_of(parsed):
        for item in source.tree.items:
            kind = _TOP.get(type(item))
            if kind is not None:
                table.setdefault((kind, item.name.text),
                                 Target(kind, item.name.text, source.path, item.name.span, item))
    return table


def _state_target(path: Path, occurrence: names.Occurrence) -> Target:
    return Target(occurrence.role, occurrence.text, path, occurrence.name.span, occurrence.node)


class Resolver:
    """Resolves the names of one parsed file; its declarations' table and its world
    are looked up once. Without ``world`` the world's bodies, joints and controllers
    are not looked up."""

    def __init__(self, project: Project, parsed: Parsed, world: bool = True):
        self.project, self.parsed, self.uses_world = project, parsed, world

    @cached_property
    def table(self) -> dict[tuple[str, str], Target]:
        return top_level(self.project, self.parsed)

    @cached_property
    def world(self):
        return self.project.world(self.parsed.path) if self.uses_world else None

    def __call__(self, occurrence: names.Occurrence) -> Target | None:
        """The declaration that ``occurrence`` declares or names, ``None`` when
        unknown."""
        path = self.parsed.path
        if occurrence.declares:
            return Target(occurrence.role, occurrence.text, path, occurrence.name.span,
                          occurrence.node)
        if occurrence.role == names.ARGUMENT:
            return self._parameter(occurrence)
        if occurrence.role in (names.FIELD, names.REGION):
            return self._member(occurrence)
        for kind in _LOOKUP.get(occurrence.role, ()):
            found = self._lookup(kind, occurrence)
            if found is not None:
                return found
        return None

    def _lookup(self, kind: str, occurrence: names.Occurrence) -> Target | None:
        scopes, path = self.parsed.scopes, self.parsed.path
        if kind == names.PARAM:
            parameter = next((p for p in occurrence.behavior.parameters
                              if p.name.text == occurrence.text), None) \
                if occurrence.behavior is not None else None
            return Target(names.PARAM, occurrence.text, path, parameter.name.span) \
                if parameter is not None else None
        if kind == names.STATE:
            found = scopes.state(occurrence, occurrence.text)
            return _state_target(path, found) if found is not None else None
        if kind == names.VAR:
            found = scopes.variable(occurrence, occurrence.text)
            return Target(names.VAR, found.text, path, found.name.span, found.node) \
                if found is not None else None
        if kind in WORLD_KINDS:
            return self._world_target(kind, occurrence.text)
        return self.table.get((kind, occurrence.text))

    def _parameter(self, occurrence: names.Occurrence) -> Target | None:
        """The behaviour parameter a named argument of an instance sets."""
        behavior = self.table.get((names.BEHAVIOR, occurrence.context))
        parameter = next((p for p in behavior.node.parameters
                          if p.name.text == occurrence.text), None) if behavior else None
        return Target(names.PARAM, parameter.name.text, behavior.path, parameter.name.span) \
            if parameter else None

    def _member(self, occurrence: names.Occurrence) -> Target | None:
        """A final or region named after a state's dot: ``pick.arrived``, ``both.left``."""
        owner = self.parsed.scopes.state(occurrence, occurrence.context)
        state = owner.node if owner is not None else None
        if not isinstance(state, ast.StateDecl):
            return None
        if occurrence.role == names.REGION:
            region = next((r for r in state.regions if r.name is not None
                           and r.name.text == occurrence.text), None)
            return Target(names.REGION, region.name.text, self.parsed.path,
                          region.name.span) if region else None
        machines = [(self.parsed.path, r.machine) for r in state.regions
                    if r.machine is not None]
        if state.instance is not None:
            behavior = self.table.get((names.BEHAVIOR, state.instance.behavior.text))
            if behavior is not None:
                machines.append((behavior.path, behavior.node.machine))
        for path, machine in machines:
            for inner in machine.states:
                if inner.final and inner.name.text == occurrence.text:
                    return Target(names.FINAL, inner.name.text, path, inner.name.span, inner)
        return None

    def _world_target(self, kind: str, name: str) -> Target | None:
        world = self.world
        if world is None:
            return None
        description = self.project.worlds.description(world.path)
        where = None
        if kind == BODY and world.has_body(name):
            where = file_line(world.body(name).where)
        elif kind == JOINT and name in world.joint_names():
            where = file_line(world.joint(name).where)
        elif kind == JOINT_GROUP and description is not None and name in description.groups:
            at = description.groups[name].at
            where = Path(at.source.path), at.span
        elif kind == CONTROLLER and description is not None \
                and name in description.processors:
            at = description.processors[name].at
            where = Path(at.source.path), at.span
        return Target(kind, name, *where) if where else None
