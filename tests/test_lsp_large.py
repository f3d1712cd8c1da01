"""A large mission in the language server: parsed piece by piece as a whole parse
would have it, and a check that the text has outrun stops between passes."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import pytest

from robocop_dsl.check import Cancelled, check_mission
from robocop_dsl.compile import WorldCache
from robocop_dsl.compile.load import _world_of
from robocop_dsl.lang import ast, parse_mission
from robocop_dsl.lsp import checking
from robocop_dsl.lsp.pieces import PieceCache, pieces
from robocop_dsl.lsp.project import Project

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO / "bench"))
from lsp_load import large_mission  # noqa: E402

TEXT = large_mission(60_000)


def spans(node, found: list) -> list:
    """Every span of a tree, depth first."""
    if isinstance(node, tuple):
        for item in node:
            spans(item, found)
    elif isinstance(node, ast.Node):
        found.append((type(node).__name__, node.span))
        for field in dataclasses.fields(node):
            spans(getattr(node, field.name), found)
    return found


def test_the_pieces_make_the_whole_parse_spans_included():
    assert len(pieces(TEXT)) > 5
    whole = parse_mission(TEXT, "large.mission")
    pieced = PieceCache().parse(TEXT, "large.mission")
    assert whole.diagnostics == pieced.diagnostics == ()
    assert pieced.mission == whole.mission
    assert spans(pieced.mission.items, []) == spans(whole.mission.items, [])


def test_an_edit_moves_the_pieces_after_it():
    cache = PieceCache()
    cache.parse(TEXT, "large.mission")
    edited = TEXT.replace("\nstate ", "\n\n# a comment\nstate ", 1)
    moved = cache.parse(edited, "large.mission")
    assert spans(moved.mission.items, []) == \
        spans(parse_mission(edited, "large.mission").mission.items, [])


def test_a_syntax_error_in_a_late_piece_is_located_in_the_file():
    lines = TEXT.split("\n")
    at = next(i for i in range(len(lines) - 1, 0, -1) if "-> failed" in lines[i])
    lines[at] = lines[at].replace("-> failed", "-> ")
    broken = "\n".join(lines)
    found = PieceCache().parse(broken, "large.mission").diagnostics
    assert [(d.span.line, d.source_line) for d in found] == \
        [(d.span.line, d.source_line) for d in parse_mission(broken, "large.mission").diagnostics]
    assert found and found[0].span.line == at + 1


def test_a_parse_that_the_text_outran_stops_between_pieces_and_keeps_them():
    cache = PieceCache()
    asked = []

    def cancelled() -> bool:
        asked.append(True)
        return len(asked) > 3

    with pytest.raises(Cancelled):
        cache.parse(TEXT, "large.mission", cancelled)
    assert len(cache._known) == 3
    assert len(pieces(TEXT)) > 3
    assert cache.parse(TEXT, "large.mission").mission == parse_mission(TEXT).mission


def test_a_check_stops_at_the_first_pass_boundary_after_the_text_changed():
    parsed = parse_mission(TEXT, str(REPO / "missions" / "large.mission"))
    _, world, _ = _world_of(parsed.mission, parsed.source, WorldCache())
    asked = []

    def cancelled() -> bool:
        asked.append(True)
        return len(asked) == 2

    with pytest.raises(Cancelled):
        check_mission(parsed.mission, parsed.source, world, REPO / "missions", cancelled)
    assert len(asked) == 2
    whole = check_mission(parsed.mission, parsed.source, world, REPO / "missions")
    assert whole.expanded is not None


def test_the_server_check_gives_nothing_for_an_outrun_text(tmp_path):
    path = tmp_path / "large.mission"
    path.write_text(TEXT)
    project = Project()
    project.open[path] = TEXT
    parsed = project.parse(path, TEXT)
    assert checking.check(project, parsed, lambda: False) == []
    calls = []
    assert checking.check(project, parsed, lambda: calls.append(1) or len(calls) > 2) is None
    assert len(calls) == 3
