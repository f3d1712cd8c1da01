"""Completion: what may be written where the cursor is, from the language's catalogue
(keywords, task and constraint types, parameters with their units, interpolators,
feedback laws, units, var kinds), the mission's own names (the vars seen where the
cursor is) and its world's."""

from __future__ import annotations

import re
from pathlib import Path

from lsprotocol import types

from ..lang import ast
from ..lang.catalogue import (BODY_SUBJECT, CONSTRAINTS, FEEDBACKS, INTERPOLATORS, TASKS,
                              Kind, Parameter)
from ..lang.formatter import comments
from ..lang.units import SI_SYMBOL, UNITS, symbols_of
from . import names
from .project import Project

Item = types.CompletionItemKind
TOP_KEYWORDS = ("mission", "library", "import", "let", "var", "world", "controller", "task",
                "constraint", "event", "behavior", "start", "state", "final", "when")
STATE_KEYWORDS = ("enter", "during", "exit", "when", "state", "final", "start")
ACTIONS = ("enable", "disable", "reset", "attach", "detach", "emit", "log")
MEASURES = ("elapsed", "time", "distance", "clearance", "force", "torque", "contact", "event",
            "not", "controller")
COMPUTED = ("time", "distance", "clearance", "force", "torque")
"""The measures an action computes with (``elapsed`` belongs to clauses)."""
AXES = ("x", "y", "z")
TASK_FIELDS = ("reached", "interpolated", "error", "position_error", "orientation_error")
BEHAVIOR_KINDS = ("task", "constraint", "body", "joint_group", "event", "target", "length",
                  "angle", "duration", "linear_velocity", "angular_velocity",
                  "linear_acceleration", "angular_acceleration", "number")
_STRINGS = re.compile(r'"([^"\\\n]|\\.)*"')
_PLACEHOLDER = re.compile(r'\blog\s+"([^"\\]|\\.)*\{\s*\w*$')
_ASSIGNMENT = re.compile(r"\s*(var\s+\w+\s*:\s*\w+|\w+)\s*=(?!=)")


def units_text(parameter: Parameter, family: str) -> str:
    """The units a parameter is written in, as a completion's detail."""
    dimension = parameter.dimension
    if dimension in SI_SYMBOL and dimension != "dimensionless":
        return f"{dimension}: {', '.join(symbols_of(dimension))}"
    if dimension in ("position", "velocity", "acceleration", "jerk"):
        return f"{dimension} of what the {family} drives"
    return parameter.kind


def _parameters(kind: Kind, family: str) -> list[types.CompletionItem]:
    return [types.CompletionItem(p.name, kind=Item.Property, detail=units_text(p, family),
                                 documentation=p.doc or None,
                                 insert_text=f"{p.name} = ")
            for p in kind.parameters]


def _kinds(registry, item_kind, call: bool) -> list[types.CompletionItem]:
    found = []
    for name in registry.names():
        kind = registry.get(name)
        takes = call and kind.parameters
        found.append(types.CompletionItem(
            name, kind=item_kind, detail=registry.family, documentation=kind.doc or None,
            insert_text=f"{name}(" if takes else name))
    return found


def _plain(words, kind, detail: str | None = None) -> list[types.CompletionItem]:
    return [types.CompletionItem(w, kind=kind, detail=detail) for w in dict.fromkeys(words)]


def _code(line: str) -> str:
    """A line without its strings' contents and its comment."""
    line = _STRINGS.sub('""', line)
    found = comments(line)
    return line[:line.index(found[0].text)] if found else line


def _blocks(lines: list[str]) -> list[str]:
    """The headers of the blocks still open at the end of ``lines``, outermost first."""
    stack: list[str] = []
    for line in lines:
        code = _code(line)
        for index, char in enumerate(code):
            if char == "{":
                stack.append(code[:index].strip())
            elif char == "}" and stack:
                stack.pop()
    return stack


class _Names:
    """The names a mission can use: its own, its imports' and its world's."""

    def __init__(self, project: Project, path: Path):
        self.project, self.path = project, path
        self.top: dict[str, list[str]] = {}
        for parsed in project.closure(path):
            for item in parsed.tree.items:
                for kind, node_type in ((names.TASK, ast.TaskDecl),
                                        (names.CONSTRAINT, ast.ConstraintDecl),
                                        (names.EVENT, ast.EventDecl),
                                        (names.BEHAVIOR, ast.BehaviorDecl),
                                        (names.CONSTANT, ast.Let)):
                    if isinstance(item, node_type):
                        self.top.setdefault(kind, []).append(item.name.text)
        parsed = project.parsed(path)
        found = parsed.occurrences if parsed else []
        self.states = [o.text for o in found
                       if o.declares and o.role in (names.STATE, names.FINAL)]
        self.vars = [o for o in found if o.declares and o.role == names.VAR]
        self.world = project.world(path)

    def items(self, kind: str, item_kind) -> list[types.CompletionItem]:
        return _plain(self.top.get(kind, []), item_kind, kind)

    def controlled(self) -> list[types.CompletionItem]:
        return self.items(names.TASK, Item.Variable) + self.items(names.CONSTRAINT,
                                                                   Item.Variable)

    def bodies(self) -> list[types.CompletionItem]:
        bodies = self.world.body_names() if self.world else []
        return _plain(bodies, Item.Struct, "body")

    def joint_groups(self) -> list[types.CompletionItem]:
        groups = self.world.group_names() if self.world else []
        return _plain(groups, Item.Module, "joint group")

    def groups(self) -> list[types.CompletionItem]:
        if self.world is None:
            return []
        return (_plain(self.world.group_names(), Item.Module, "joint group")
                + _plain(self.world.joint_names(), Item.Field, "joint"))

    def state_items(self) -> list[types.CompletionItem]:
        return _plain(self.states, Item.Class, "state")

    def values(self) -> list[types.CompletionItem]:
        return self.items(names.CONSTANT, Item.Constant) + self.bodies()

    def variables(self, line: int) -> list[types.CompletionItem]:
        """The vars seen on the 1-based ``line``: those at the top of the file and those
        of the machines (behaviour bodies, regions) around it."""
        seen = []
        for declared in self.vars:
            span = declared.machines[0].span
            if (len(declared.machines) == 1 and declared.behavior is None) \
                    or span.line <= line <= span.end_line:
                seen.append(types.CompletionItem(declared.text, kind=Item.Variable,
                                                 detail=f"var: {declared.node.kind.text}"))
        return list({item.label: item for item in seen}.values())

    def numbers(self, line: int) -> list[types.CompletionItem]:
        """What stands for a number: the vars seen on ``line`` and the constants."""
        return self.variables(line) + self.items(names.CONSTANT, Item.Constant)

    def expression(self, line: int) -> list[types.CompletionItem]:
        """What an action computes with: numbers, measures and bodies (``BODY.position``)."""
        return self.numbers(line) + _plain(COMPUTED, Item.Keyword) + self.bodies()


def _units(dimension: str | None) -> list[types.CompletionItem]:
    units = [u for u in UNITS.values() if dimension in (None, u.dimension)]
    return [types.CompletionItem(u.symbol, kind=Item.Unit, detail=u.dimension) for u in units]


def _parameter_of(block: str | None, name: str) -> tuple[Parameter | None, str]:
    """The catalogue parameter ``name`` of the declaration whose block is open."""
    match = re.match(r"(task|constraint)\s+\w+\s*:\s*(\w+)", block or "")
    if not match:
        return None, ""
    registry = TASKS if match.group(1) == "task" else CONSTRAINTS
    kind = registry.get(match.group(2))
    return (kind.parameter(name) if kind else None), match.group(1)


def _value_items(parameter: Parameter | None, known: _Names) -> list[types.CompletionItem]:
    if parameter is None:
        return known.values()
    if parameter.kind == "interpolator":
        return _kinds(INTERPOLATORS, Item.Function, True)
    if parameter.kind == "feedback":
        return _kinds(FEEDBACKS, Item.Function, True)
    if parameter.kind == "body":
        return _plain(["world"], Item.Keyword) + known.bodies()
    if parameter.kind == "target":
        return (_plain(["current"], Item.Keyword)
                + [types.CompletionItem("pose", kind=Item.Function, insert_text="pose(")]
                + known.values())
    return known.items(names.CONSTANT, Item.Constant)


def complete(project: Project, path: Path, line: int, character: int
             ) -> list[types.CompletionItem]:
    """What may be written at the 0-based position (a character column) in the mission
    at ``path``, each item an edit of the word the position ends."""
    lines = (project.text(path) or "").split("\n")
    current = lines[line][:character] if line < len(lines) else ""
    start = len(current) - len(re.search(r"\w*$", current).group())
    typed = types.Range(types.Position(line, start), types.Position(line, len(current)))
    items = _items(project, path, lines, line, current)
    for item in items:
        item.text_edit = types.TextEdit(typed, item.insert_text or item.label)
        item.insert_text = None
    return items


def _items(project: Project, path: Path, lines: list[str], line: int, current: str
           ) -> list[types.CompletionItem]:
    """What may be written after ``current``, the start of the 0-based ``line``."""
    before = re.sub(r"\w*$", "", _code(current))
    blocks = _blocks(lines[:line] + [current])
    block = blocks[-1] if blocks else None
    known = _Names(project, path)

    computed = _computed(current, before, block, known, line + 1)
    if computed is not None:
        return computed
    if match := re.match(r"\s*(task|constraint)\s+\w+\s*:\s*$", before):
        registry = TASKS if match.group(1) == "task" else CONSTRAINTS
        return _kinds(registry, Item.Class, False)
    if match := re.match(r"\s*(task|constraint)\s+\w+\s*:\s*(\w+)\s*\(\s*$", before):
        registry = TASKS if match.group(1) == "task" else CONSTRAINTS
        kind = registry.get(match.group(2))
        if kind is None:
            return known.bodies() + known.groups()
        return known.bodies() if kind.subject == BODY_SUBJECT else known.groups()
    if match := re.search(r"(\w+)\s*\.\s*$", before):
        return _fields(match.group(1), known)
    if re.search(r"\b(enable|disable|reset)\s+(\w+\s*,\s*)*$", before):
        return known.controlled()
    if re.search(r"->\s*$", before) or re.match(r"\s*start\s+$", before):
        return known.state_items()
    if re.search(r"\b(emit|event)\s+$", before):
        return known.items(names.EVENT, Item.Event)
    if re.search(r"\b(attach|detach|to)\s+$|\b(distance|force|torque)\s*\(\s*(\w+\s*,\s*)?$",
                 before):
        return known.bodies()
    if re.search(r"\b(clearance|contact)\s*\(\s*(\w+\s*,\s*)?$", before):
        return known.bodies() + known.joint_groups()
    if match := re.match(r"\s*(state|region)\s+\w+\s*:\s*$", before):
        extra = _plain(["parallel"], Item.Keyword) if match.group(1) == "state" else []
        return extra + known.items(names.BEHAVIOR, Item.Function)
    if re.match(r"\s*controller\s+$", before):
        controllers = known.world.controller_names() if known.world else []
        return _plain(controllers, Item.Module, "controller")
    if match := re.search(r"(\w+)\s*\(([^()]*)$", before):
        return _call_items(match.group(1), match.group(2), known)
    if re.search(r"(\d\.?|\])\s+$", before):
        setting = re.match(r"\s*(\w+)\s*=", before)
        parameter, _ = _parameter_of(block, setting.group(1)) if setting else (None, "")
        dimension = parameter.dimension if parameter and parameter.dimension in SI_SYMBOL \
            else None
        return _units(dimension)
    if match := re.match(r"\s*(\w+)\s*=\s*$", before):
        parameter, _ = _parameter_of(block, match.group(1))
        return _value_items(parameter, known)
    if re.search(r"\.target\s*=\s*$", before):
        return _value_items(TASKS.get("body_pose").parameter("target"), known)
    if re.search(r"\b(when|and|or|not)\s+$|\(\s*$", before):
        return (_plain(MEASURES, Item.Keyword) + known.variables(line + 1) + known.controlled()
                + known.state_items())
    if re.match(r"\s*$", before):
        return _line_start(block, known, line + 1)
    if re.search(r":\s*$", before) and block and block.startswith("behavior"):
        return _plain(BEHAVIOR_KINDS, Item.TypeParameter)
    return known.values() + known.controlled() + known.state_items()


def _in_actions(block: str | None) -> bool:
    """Whether the innermost open block is a list of actions."""
    return bool(block and (re.match(r"(enter|during|exit)\b", block) or "->" in block))


def _computed(current: str, before: str, block: str | None, known: _Names, line: int
              ) -> list[types.CompletionItem] | None:
    """Where a var, a number or a measure goes (a log text's ``{``, a var's kind, an
    expression, a comparison, a vector, an axis), on the 1-based ``line``; ``None``
    elsewhere."""
    if _PLACEHOLDER.search(current):
        return known.numbers(line)
    if re.match(r"\s*var\s+\w+\s*:\s*$", before):
        from ..check.variables import KINDS

        return _plain(KINDS, Item.TypeParameter, "var kind")
    if match := re.search(r"\b(force|torque)\s*\(\s*\w*\s*\)\s*\.\s*$", before):
        return _plain(AXES, Item.Field, match.group(1))
    if re.search(r"\w\s*\.\s*position\s*\.\s*$", before):
        return _plain(AXES, Item.Field, "position")
    statement = before.rsplit("{", 1)[-1]
    assignment = _ASSIGNMENT.match(statement)
    if assignment and (assignment.group(1).startswith("var") or _in_actions(block)) \
            and re.search(r"([-+*/=]|(^|[^\w\s])\s*\()\s*$", statement):
        return known.expression(line)
    if re.search(r"\[[^\[\]]*[\[,]\s*$", statement):
        return known.numbers(line) if _in_actions(block) else known.items(names.CONSTANT,
                                                                          Item.Constant)
    if re.search(r"\bwhen\b.*(?<!-)[<>]=?\s*$", statement):
        return known.numbers(line)
    return None


def _fields(owner: str, known: _Names) -> list[types.CompletionItem]:
    if owner == "controller":
        return _plain(["failed"], Item.Field)
    if owner in known.top.get(names.TASK, []) or owner in known.top.get(names.CONSTRAINT, []):
        settable = ("target", "gain", "weight")
        return _plain(TASK_FIELDS, Item.Field, "condition") + _plain(settable, Item.Property,
                                                                      "settable")
    if known.world is not None and known.world.has_body(owner):
        return _plain(["position"], Item.Field, "body")
    return _plain(["visits", "done"], Item.Field, "state")


def _call_items(call: str, written: str, known: _Names) -> list[types.CompletionItem]:
    """Inside ``call(...)``: its parameters (interpolators, feedback laws, pose) or,
    for a behaviour instance, values."""
    if "=" in written.rsplit(",", 1)[-1]:
        return known.values()
    for registry, family in ((INTERPOLATORS, "interpolator"), (FEEDBACKS, "feedback")):
        kind = registry.get(call)
        if kind is not None:
            return _parameters(kind, family)
    if call == "pose":
        return _plain(["position", "rpy"], Item.Property)
    if call in known.top.get(names.BEHAVIOR, []):
        return known.values() + known.controlled()
    return known.values()


def _line_start(block: str | None, known: _Names, line: int) -> list[types.CompletionItem]:
    if block is None:
        return _plain(TOP_KEYWORDS, Item.Keyword)
    declaration = re.match(r"(task|constraint)\s+\w+\s*:\s*(\w+)", block)
    if declaration:
        registry = TASKS if declaration.group(1) == "task" else CONSTRAINTS
        kind = registry.get(declaration.group(2))
        return _parameters(kind, declaration.group(1)) if kind else []
    if _in_actions(block):
        return _plain(ACTIONS, Item.Keyword) + known.controlled() + known.variables(line)
    keywords = STATE_KEYWORDS + (("region",) if block.endswith("parallel") else ())
    keywords += ("var",) if re.match(r"(behavior|region)\b", block) else ()
    return _plain(keywords, Item.Keyword)
