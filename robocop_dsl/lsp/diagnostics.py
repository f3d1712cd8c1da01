"""The checker's diagnostics as the protocol's: code, range, hint, the places they name
as related information (the first declaration of a duplicate, the behaviour instance
that exposed a problem) and, in ``data``, the quick fixes their words call for. A
problem in another file (an imported one, the world) is shown on the statement that
brings that file in; its fixes edit that file."""

from __future__ import annotations

import re
from pathlib import Path

from lsprotocol import types
from pygls.exceptions import JsonRpcInvalidParams

from ..diagnostics import Diagnostic, Span
from ..lang import ast
from .fixes import Fix, fixes
from .positions import (Encoding, location, path_to_uri, to_range, unknown_document,
                        uri_to_path)
from .project import Parsed, Project

SOURCE = "robocop-mission"
_AT_FILE = re.compile(r"([\w./\\-]+\.(?:mission|yaml|urdf)):(\d+)(?::(\d+))?")
_AT_LINE = re.compile(r"\bline (\d+)\b")


def _places(text: str, file: Path) -> list[tuple[Path, Span]]:
    """The places a note or hint names: ``FILE:LINE[:COL]``, or ``line N`` of
    ``file``, the one the diagnostic is in."""
    found = [(Path(m.group(1)).resolve(), Span.point(int(m.group(2)), int(m.group(3) or 1)))
             for m in _AT_FILE.finditer(text)]
    return found + [(file, Span.point(int(m.group(1)))) for m in _AT_LINE.finditer(text)]


def _related(diagnostic: Diagnostic, file: Path) -> list:
    related = []
    for note in diagnostic.notes:
        places = _places(note, file) or [(file, diagnostic.span)]
        related += [types.DiagnosticRelatedInformation(location(p, s), note) for p, s in places]
    if diagnostic.hint:
        related += [types.DiagnosticRelatedInformation(location(p, s), diagnostic.hint)
                    for p, s in _places(diagnostic.hint, file)]
    return related


def _carrier(project: Project, parsed: Parsed, file: Path) -> Span | None:
    """The statement of ``parsed`` that brings ``file`` in: the import whose files reach
    it, else the world declaration."""
    for statement, imported in parsed.imports():
        if any(p.path == file for p in project.closure(imported)):
            return statement.path.span
    world = parsed.tree.first(ast.WorldDecl)
    return world.path.span if world is not None else None


def fix_data(found: list[Fix]) -> list[dict] | None:
    """Fixes as a diagnostic's ``data`` (which the client sends back with a code action
    request): spans in characters, turned into the client's encoding by
    :func:`code_actions`."""
    return [{"title": f.title, "uri": path_to_uri(f.path), "line": f.span.line,
             "column": f.span.column, "end_line": f.span.end_line,
             "end_column": f.span.end_column, "text": f.text, "preferred": f.preferred}
            for f in found] or None


def code_actions(found: list[types.Diagnostic], encoding: Encoding) -> list[types.CodeAction]:
    """The quick fixes that this server's diagnostics among ``found`` carry in their
    ``data``. Raises :class:`~pygls.exceptions.JsonRpcInvalidParams` for ``data`` this
    server did not write: not a list of fixes, or a fix outside its file."""
    actions = []
    for diagnostic in found:
        if diagnostic.source != SOURCE:
            continue
        for fix in _fixes_of(diagnostic.data):
            path = uri_to_path(fix["uri"])
            span = Span(fix["line"], fix["column"], fix["end_line"], fix["end_column"])
            _within(encoding, path, span)
            edit = encoding.edit(path, types.TextEdit(to_range(span), fix["text"]))
            actions.append(types.CodeAction(
                fix["title"], kind=types.CodeActionKind.QuickFix, diagnostics=[diagnostic],
                is_preferred=fix["preferred"] or None,
                edit=types.WorkspaceEdit(changes={fix["uri"]: [edit]})))
    return actions


_FIX_FIELDS = {"title": str, "uri": str, "line": int, "column": int, "end_line": int,
               "end_column": int, "text": str, "preferred": bool}


def _fixes_of(data) -> list[dict]:
    """The fixes of a diagnostic's ``data`` as :func:`fix_data` wrote them."""
    if data is None:
        return []
    if not isinstance(data, list) or not all(
            isinstance(fix, dict) and all(isinstance(fix.get(key), kind)
                                          for key, kind in _FIX_FIELDS.items())
            for fix in data):
        raise JsonRpcInvalidParams("a diagnostic's data is not this server's quick fixes: "
                                   f"each needs {', '.join(_FIX_FIELDS)}")
    return data


def _within(encoding: Encoding, path: Path, span: Span) -> None:
    """Refuse a fix whose span is not in the current text of its file."""
    source = encoding.source(path)
    if source is None:
        raise JsonRpcInvalidParams(unknown_document(path))
    ends = ((span.line, span.column), (span.end_line, span.end_column))
    if not all(1 <= line <= source.line_count and 1 <= column <= len(source.line(line)) + 1
               for line, column in ends) or ends[1] < ends[0]:
        raise JsonRpcInvalidParams(f"a quick fix's range {span.line}:{span.column}-"
                                   f"{span.end_line}:{span.end_column} is not in "
                                   f"{path.name} (lines 1 to {source.line_count})")


def convert(project: Project, parsed: Parsed, diagnostic: Diagnostic) -> types.Diagnostic:
    """One checker diagnostic of the mission ``parsed`` as a protocol diagnostic, its
    range in characters."""
    path = parsed.path
    file = Path(diagnostic.file).resolve() if diagnostic.file else path
    message = diagnostic.message + (f"\nhint: {diagnostic.hint}" if diagnostic.hint else "")
    related = _related(diagnostic, file)
    span = diagnostic.span
    source = parsed.result.source if file == path else project.source(file)
    found = fixes(diagnostic, file, source)
    if file != path:
        message = f"{diagnostic.location()}: {message}"
        related.insert(0, types.DiagnosticRelatedInformation(location(file, span),
                                                             diagnostic.message))
        span = _carrier(project, parsed, file)
    severity = (types.DiagnosticSeverity.Error if diagnostic.is_error
                else types.DiagnosticSeverity.Warning)
    return types.Diagnostic(range=to_range(span), message=message, severity=severity,
                            code=diagnostic.code, source=SOURCE,
                            related_information=related or None, data=fix_data(found))
