"""Signature help: inside the parentheses of a call, what it takes and which argument
the cursor is on. Calls are interpolators and feedback laws (``otg(``, ``pid(``),
``pose(`` (a target, or a tolerance after ``tolerance =``) and ``twist(``, behaviour
instances (``reach(``), a task or constraint type's subjects (``body_pose(``) and the
measures (``distance(``, ``clearance(``, ``force(``, ``torque(``, ``contact(``)."""

from __future__ import annotations

import re
from pathlib import Path

from lsprotocol import types

from ..lang import ast
from ..lang.catalogue import (BODY_SUBJECT, COLLISION_SETS, CONSTRAINTS, FEEDBACKS,
                              INTERPOLATORS, TASKS, TOLERANCES, Kind)
from ..lang.syntax_errors import CONTINUED, code_of
from .completion import units_text
from .project import Project

_MEASURES = {
    "distance": (("body", "a body"), ("body", "a body")),
    "clearance": (("set", "a body or a joint group"), ("set", "a body or a joint group")),
    "force": (("body", "a body with a force sensor"),),
    "torque": (("body", "a body with a force sensor"),),
    "contact": (("set", "a body or a joint group"), ("set", "a body or a joint group")),
}
_TARGET_POSE = (("position", "[x, y, z] with a length unit: where the body goes"),
                ("rpy", "[roll, pitch, yaw] with an angle unit: how it is turned"))
_SUBJECTS = {BODY_SUBJECT: (("body", "the body it drives"),),
             COLLISION_SETS: (("first", "a body or a joint group"),
                              ("second", "a body or a joint group"))}
_DECLARED = re.compile(r"\b(task|constraint)\s+\w+\s*:\s*$")


def _statement(lines: list[str], line: int, character: int) -> str:
    """The code of the statement up to the 0-based position: the lines before it that
    it continues, strings and comments blanked."""
    first = line
    while first > 0 and CONTINUED.search(code_of(lines[first - 1])):
        first -= 1
    return "\n".join(code_of(text) for text in lines[first:line]
                     + [lines[line][:character]])


def _open_call(code: str) -> tuple[str, str, str] | None:
    """The innermost call still open at the end of ``code`` (a vector still open inside
    it is part of its argument): the code before its name, its name and what is written
    inside it so far."""
    depth = 0
    for index in range(len(code) - 1, -1, -1):
        char = code[index]
        if char in ")]":
            depth += 1
        elif char in "([":
            if depth:
                depth -= 1
            elif char == "(":
                name = re.search(r"(\w+)\s*$", code[:index])
                if name is None:
                    return None
                return code[:name.start()], name.group(1), code[index + 1:]
    return None


def _arguments(written: str) -> list[str]:
    """The arguments written so far, split at the commas outside brackets."""
    found, depth, current = [], 0, ""
    for char in written:
        if char in "([":
            depth += 1
        elif char in ")]":
            depth -= 1
        elif char == "," and depth == 0:
            found.append(current)
            current = ""
            continue
        current += char
    return [*found, current]


def _signature(name: str, parameters, documentation: str, written: str
               ) -> types.SignatureHelp:
    """``name(p1, p2, ...)`` with each parameter's documentation, the active one the
    argument the cursor is in (by its name when it is written ``NAME = ...``)."""
    label, offsets = f"{name}(", []
    for index, (parameter, _) in enumerate(parameters):
        label += ", " if index else ""
        offsets.append((len(label), len(label) + len(parameter)))
        label += parameter
    label += ")"
    arguments = _arguments(written)
    named = re.match(r"\s*(\w+)\s*=", arguments[-1])
    names = [parameter.split(":")[0] for parameter, _ in parameters]
    active = names.index(named.group(1)) if named and named.group(1) in names \
        else len(arguments) - 1
    information = types.SignatureInformation(
        label, documentation=types.MarkupContent(types.MarkupKind.Markdown, documentation),
        parameters=[types.ParameterInformation(
            offset, types.MarkupContent(types.MarkupKind.Markdown, doc))
            for offset, (_, doc) in zip(offsets, parameters)])
    return types.SignatureHelp([information], active_signature=0,
                               active_parameter=min(active, max(len(parameters) - 1, 0)))


def _catalogue(kind: Kind, family: str) -> list[tuple[str, str]]:
    found = []
    for parameter in kind.parameters:
        need = "required" if parameter.required else (
            f"default {parameter.default}" if parameter.default is not None else "optional")
        doc = f": {parameter.doc}" if parameter.doc else ""
        found.append((parameter.name, f"{units_text(parameter, family)}; {need}{doc}"))
    return found


def _behavior(project: Project, path: Path, name: str) -> ast.BehaviorDecl | None:
    for parsed in project.closure(path):
        for behavior in parsed.tree.behaviors:
            if behavior.name.text == name:
                return behavior
    return None


def signature_help(project: Project, path: Path, line: int, character: int
                   ) -> types.SignatureHelp | None:
    """What the call around the 0-based position (a character column) takes."""
    lines = (project.text(path) or "").split("\n")
    if line >= len(lines):
        return None
    call = _open_call(_statement(lines, line, character))
    if call is None:
        return None
    before, name, written = call
    if name in ("pose", "twist") and re.search(r"\btolerance\s*=\s*$", before):
        kind = TOLERANCES.get(name)
        return _signature(name, _catalogue(kind, "task"), kind.doc, written)
    if name == "pose":
        return _signature(name, _TARGET_POSE, "a target pose", written)
    for registry, family in ((INTERPOLATORS, "interpolator"), (FEEDBACKS, "task")):
        kind = registry.get(name)
        if kind is not None:
            return _signature(name, _catalogue(kind, family), f"{registry.family}: {kind.doc}",
                              written)
    declared = _DECLARED.search(before)
    if declared is not None:
        kind = (TASKS if declared.group(1) == "task" else CONSTRAINTS).get(name)
        if kind is None:
            return None
        subjects = _SUBJECTS.get(kind.subject, (("joint_group", "the joints it drives"),))
        return _signature(name, subjects, kind.doc, written)
    if name in _MEASURES:
        return _signature(name, _MEASURES[name], f"the measure {name}", written)
    behavior = _behavior(project, path, name)
    if behavior is None:
        return None
    parameters = [(f"{p.name.text}: {p.kind.text}",
                   "optional: it has a default" if p.default is not None else "required")
                  for p in behavior.parameters]
    outcomes = ", ".join(s.name.text for s in behavior.machine.states if s.final)
    return _signature(name, parameters, f"behavior {name}; outcomes: {outcomes or 'none'}",
                      written)
