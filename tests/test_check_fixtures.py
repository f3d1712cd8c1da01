"""Broken missions in tests/fixtures/invalid: each gives exactly the diagnostics beside it."""

import re
from pathlib import Path

import pytest

from robocop_dsl.compile import WorldCache, check_file

REPO = Path(__file__).resolve().parent.parent
INVALID = sorted((REPO / "tests" / "fixtures" / "invalid").glob("*.mission"))
VALID = sorted((REPO / "tests" / "fixtures" / "valid").glob("*.mission"))
CACHE = WorldCache()


@pytest.fixture(autouse=True)
def _in_repository(monkeypatch):
    """Messages name other files relative to the working folder: the repository's."""
    monkeypatch.chdir(REPO)


def _line(diagnostic) -> str:
    name = Path(diagnostic.file).name
    where = f"{diagnostic.span.line}:{diagnostic.span.column}:" if diagnostic.span else ""
    return f"{name}:{where} {diagnostic.severity}[{diagnostic.code}]: {diagnostic.message}"


def test_there_are_at_least_forty_broken_missions():
    """The corpus covers the checks with many examples, thirty of them composite."""
    assert len(INVALID) >= 40
    assert len([p for p in INVALID if p.stem.startswith("composite_")]) >= 30


@pytest.mark.parametrize("path", INVALID, ids=lambda p: p.stem)
def test_invalid_fixture(path):
    """Code, line, column and message of every diagnostic match the .expected file."""
    expected = path.with_suffix(".expected").read_text().splitlines()
    result = check_file(path, cache=CACHE)
    assert [_line(d) for d in result.diagnostics] == expected
    assert all(d.source_line for d in result.diagnostics if d.span)
    if path.stem.startswith("composite_"):
        assert all(d.span is not None for d in result.diagnostics)


@pytest.mark.parametrize("path", VALID, ids=lambda p: p.stem)
def test_valid_fixture(path):
    """The fixtures' base mission is clean."""
    assert check_file(path, cache=CACHE).diagnostics == ()


def test_every_documented_code_has_a_fixture():
    """docs/diagnostics.md lists each code once, and the fixtures exercise them all."""
    text = (REPO / "docs" / "diagnostics.md").read_text()
    documented = re.findall(r"^### `([a-z-]+)`", text, flags=re.MULTILINE)
    assert len(documented) == len(set(documented))
    exercised = {m for p in INVALID
                 for m in re.findall(r"\[([a-z-]+)\]", p.with_suffix(".expected").read_text())}
    world_and_campaign = set(re.findall(r"^### `([a-z-]+)`", text.split("## World files", 1)[1],
                                        flags=re.MULTILINE))
    not_from_fixtures = {"unreadable-file"} | world_and_campaign
    assert set(documented) - not_from_fixtures <= exercised
    assert exercised <= set(documented)


def test_one_rendering_exactly():
    """The full text rendering: headline, source line, caret and hint."""
    result = check_file(REPO / "tests/fixtures/invalid/dimension_joint_limit.mission",
                        cache=CACHE)
    assert result.diagnostics[0].render().split("\n", 1)[1] == (
        " 6 |     max_velocity     = 1 m\n"
        "   |                          ^\n"
        "   = hint: a number without a unit is SI (rad/s)")


def test_every_code_the_package_gives_is_documented():
    """Each diagnostic code written in the package has its entry in docs/diagnostics.md."""
    text = (REPO / "docs" / "diagnostics.md").read_text()
    documented = set(re.findall(r"^### `([a-z-]+)`", text, flags=re.MULTILINE))
    given = {code for path in (REPO / "robocop_dsl").rglob("*.py")
             for code in re.findall(r"(?:error|warning)\(\s*\"([a-z]+(?:-[a-z]+)+)\"",
                                    path.read_text())}
    assert given - documented == set()
