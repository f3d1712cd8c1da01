"""Semantic highlighting: each name coloured by what it names, on top of the
TextMate grammar's keywords, numbers, strings and comments."""

from __future__ import annotations

from lsprotocol import types

from . import names
from .project import Parsed

TOKEN_TYPES = ["variable", "class", "enumMember", "function", "parameter", "event",
               "type", "property", "namespace", "macro", "struct"]
MODIFIERS = ["declaration", "readonly"]
_ROLES = {names.TASK: "variable", names.CONSTRAINT: "variable", names.CONTROLLED: "variable",
          names.OWNER: "variable", names.STATE: "class", names.FINAL: "enumMember",
          names.REGION: "namespace", names.BEHAVIOR: "function", names.PARAM: "parameter",
          names.EVENT: "event", names.TYPE: "type", names.KIND: "type", names.CALL: "function",
          names.SETTING: "property", names.ARGUMENT: "property", names.FIELD: "property",
          names.CONSTANT: "macro", names.VALUE: "struct", names.SUBJECT: "struct",
          names.BODY: "struct", names.CONTROLLER: "namespace", names.UNIT: "type",
          names.OUTCOME: "enumMember"}
LEGEND = types.SemanticTokensLegend(token_types=TOKEN_TYPES, token_modifiers=MODIFIERS)


def semantic_tokens(parsed: Parsed) -> types.SemanticTokens:
    """The document's names as relative-encoded tokens (line, start, length, type,
    modifiers), in document order."""
    data: list[int] = []
    last_line, last_start = 0, 0
    ordered = sorted(parsed.occurrences, key=lambda o: (o.name.span.line, o.name.span.column))
    for occurrence in ordered:
        span = occurrence.name.span
        line, start = span.line - 1, span.column - 1
        modifiers = 1 if occurrence.declares else 0
        if occurrence.role == names.CONSTANT:
            modifiers |= 2
        delta_start = start - last_start if line == last_line else start
        data += [line - last_line, delta_start, len(occurrence.text),
                 TOKEN_TYPES.index(_ROLES[occurrence.role]), modifiers]
        last_line, last_start = line, start
    return types.SemanticTokens(data=data)
