"""Semantic highlighting: each name coloured by the kind of what it names, on top of the
TextMate grammar's keywords, numbers, strings and comments. A name has the token type
of its kind where it is declared and wherever it is used (a state named after ``->``,
a var read in a log text, a body in the world): one token type per kind of name."""

from __future__ import annotations

from typing import Callable

from lsprotocol import types

from . import names
from .resolve import BODY, CONTROLLER, JOINT, JOINT_GROUP, Resolver
from .project import Parsed, Project

KINDS = {
    names.TASK: "method", names.CONSTRAINT: "interface", names.STATE: "class",
    names.FINAL: "enumMember", names.REGION: "namespace", names.BEHAVIOR: "function",
    names.PARAM: "parameter", names.EVENT: "event", names.CONSTANT: "macro",
    names.VAR: "variable", BODY: "struct", JOINT_GROUP: "enum", JOINT: "typeParameter",
    CONTROLLER: "decorator", names.TYPE: "type", names.SETTING: "property",
    names.UNIT: "number", names.OUTCOME: "modifier",
}
"""The token type of each kind of name (the words of the vocabulary: types, parameter
names, units, outcomes, are kinds too)."""
_UNRESOLVED = {
    names.CONTROLLED: names.TASK, names.OWNER: names.STATE, names.VALUE: names.CONSTANT,
    names.SUBJECT: BODY, names.SET: BODY, names.READ: names.VAR, names.ASSIGNED: names.VAR,
    names.CALL: names.TYPE, names.KIND: names.TYPE, names.ARGUMENT: names.SETTING,
    names.FIELD: names.SETTING,
}
"""The kind of a name that resolves to nothing: the one its place most often names
(the vocabulary's calls and kinds are types, its arguments and fields settings)."""
_VOCABULARY = (names.TYPE, names.SETTING, names.UNIT, names.OUTCOME)
TOKEN_TYPES = list(dict.fromkeys(KINDS.values()))
MODIFIERS = ["declaration", "readonly"]
LEGEND = types.SemanticTokensLegend(token_types=TOKEN_TYPES, token_modifiers=MODIFIERS)
_INDEX = {kind: TOKEN_TYPES.index(token) for kind, token in KINDS.items()}


def kind_of(resolver: Resolver, occurrence: names.Occurrence) -> str:
    """The kind of what ``occurrence`` declares or names."""
    if occurrence.declares or occurrence.role in _VOCABULARY:
        return occurrence.role
    target = resolver(occurrence)
    if target is not None and target.kind in KINDS:
        return target.kind
    return _UNRESOLVED.get(occurrence.role, occurrence.role)


def semantic_tokens(project: Project, parsed: Parsed,
                    column: Callable[[int, int], int] = lambda line, character: character
                    ) -> types.SemanticTokens:
    """The document's names as relative-encoded tokens (line, start, length, type,
    modifiers), in document order; ``column(line, character)`` gives a 0-based
    character column in the client's code units (names are ASCII: lengths stay)."""
    data: list[int] = []
    last_line, last_start = 0, 0
    resolver = Resolver(project, parsed)
    ordered = sorted(parsed.occurrences, key=lambda o: (o.name.span.line, o.name.span.column))
    for occurrence in ordered:
        span = occurrence.name.span
        line = span.line - 1
        start = column(line, span.column - 1)
        kind = kind_of(resolver, occurrence)
        modifiers = (1 if occurrence.declares else 0) | (2 if kind == names.CONSTANT else 0)
        delta_start = start - last_start if line == last_line else start
        data += [line - last_line, delta_start, len(occurrence.text),
                 _INDEX[kind], modifiers]
        last_line, last_start = line, start
    return types.SemanticTokens(data=data)
