"""Semantic highlighting: each name coloured by what it names, on top of the
TextMate grammar's keywords, numbers, strings and comments. A name read as a value
takes the colour of its declaration: a var, a constant or a behaviour parameter looks
the same where it is declared and where it is used."""

from __future__ import annotations

from lsprotocol import types

from . import names
from .navigation import resolve, top_level
from .project import Parsed, Project

TOKEN_TYPES = ["variable", "class", "enumMember", "function", "parameter", "event",
               "type", "property", "namespace", "macro", "struct"]
MODIFIERS = ["declaration", "readonly"]
_ROLES = {names.TASK: "variable", names.CONSTRAINT: "variable", names.CONTROLLED: "variable",
          names.OWNER: "variable", names.STATE: "class", names.FINAL: "enumMember",
          names.REGION: "namespace", names.BEHAVIOR: "function", names.PARAM: "parameter",
          names.EVENT: "event", names.TYPE: "type", names.KIND: "type", names.CALL: "function",
          names.SETTING: "property", names.ARGUMENT: "property", names.FIELD: "property",
          names.CONSTANT: "macro", names.VALUE: "struct", names.SUBJECT: "struct",
          names.BODY: "struct", names.SET: "struct", names.CONTROLLER: "namespace",
          names.UNIT: "type", names.OUTCOME: "enumMember", names.VAR: "variable",
          names.READ: "variable", names.ASSIGNED: "variable"}
_READ_AS_DECLARED = (names.READ, names.VALUE)
LEGEND = types.SemanticTokensLegend(token_types=TOKEN_TYPES, token_modifiers=MODIFIERS)


def _kind(project: Project, parsed: Parsed, occurrence: names.Occurrence, table) -> str:
    """What colours ``occurrence``: what it declares, the declaration in the mission a
    value names, else its role."""
    if occurrence.role in _READ_AS_DECLARED:
        target = resolve(project, parsed, occurrence, table, world=False)
        if target is not None and target.kind in _ROLES:
            return target.kind
    return occurrence.role


def semantic_tokens(project: Project, parsed: Parsed) -> types.SemanticTokens:
    """The document's names as relative-encoded tokens (line, start, length, type,
    modifiers), in document order."""
    data: list[int] = []
    last_line, last_start = 0, 0
    table = top_level(project, parsed)
    ordered = sorted(parsed.occurrences, key=lambda o: (o.name.span.line, o.name.span.column))
    for occurrence in ordered:
        span = occurrence.name.span
        line, start = span.line - 1, span.column - 1
        kind = _kind(project, parsed, occurrence, table)
        modifiers = 1 if occurrence.declares else 0
        if kind == names.CONSTANT:
            modifiers |= 2
        delta_start = start - last_start if line == last_line else start
        data += [line - last_line, delta_start, len(occurrence.text),
                 TOKEN_TYPES.index(_ROLES[kind]), modifiers]
        last_line, last_start = line, start
    return types.SemanticTokens(data=data)
