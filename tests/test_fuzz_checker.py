"""Fuzzing ``check``: missions generated from the grammar, and the real missions and
worlds mutated (deep nesting, huge numbers, odd bytes and line breaks, alias bombs).

Whatever the input, checking never raises, and every diagnostic renders in each format
and is located: a file, a line within that file and a column within that line (or
just past its end), lines counted the way the file's parser counts them.

Each test runs ``ROBOCOP_FUZZ_EXAMPLES`` inputs (100 by default: a CI-sized batch);
``bench/fuzz_checker.py`` runs 10,000 in batches.
"""

from __future__ import annotations

import functools
import os
import shutil
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra.lark import from_lark
from lark import Lark

from robocop_dsl.compile import WorldCache, check_file
from robocop_dsl.diagnostics import MISSION_BREAKS, XML_BREAKS, YAML_BREAKS, SourceFile
from robocop_dsl.resources import GRAMMAR_DIR, ROBOTS_DIR
from robocop_dsl.sources import MISSION, URDF, WORLD, editor_lines, kind_of

REPO = Path(__file__).resolve().parent.parent
EXAMPLES = int(os.environ.get("ROBOCOP_FUZZ_EXAMPLES", "100"))
FUZZ = settings(max_examples=EXAMPLES, deadline=None, database=None,
                suppress_health_check=list(HealthCheck))
MISSIONS = sorted([*(REPO / "missions").glob("*.mission"),
                   *(REPO / "tests" / "fixtures").glob("*/*.mission")])
WORLDS = sorted(ROBOTS_DIR.glob("*/*.yaml"))
BREAKS = {MISSION: MISSION_BREAKS, WORLD: YAML_BREAKS, URDF: XML_BREAKS}
CACHE = WorldCache()

# Pieces a mutation inserts: nesting, numbers, odd characters and line breaks.
PIECES = ["not " * 70, "not " * 500, "(" * 80, ")" * 80, "{" * 80, "}" * 80,
          "[" * 200, "]" * 40, "(elapsed > 1 s and " * 70, "state s {\n" * 40,
          "9" * 5000, "1e999", "-1e-999", "0x1F", "nan", "inf", "1" * 400 + " rad/s",
          "\f", "\v", "\r", "\r\n", "\u2028", "\u2029", "\x85", "\x1c", "\x00", "\ufeff",
          "\t", '"', "#", "\\", "\n" * 3, "é", "\U0001F916", "\u202e", ":", "- ", "&a ",
          "*a", "!!python/object/apply:os.system ['true']", "<<: *a\n", "? [a]\n",
          "w" * 300, "../" * 40, "/dev/zero", "/etc/passwd", "%", ","]
YAML_PIECES = ["x: &a [1, 2, 3, 4, 5, 6, 7, 8, 9]\n" + "".join(
    f"{b}: &{b} [{', '.join([f'*{a}'] * 9)}]\n" for a, b in zip("abcdefgh", "bcdefghi")),
    "models: " + "[" * 5000 + "]" * 5000 + "\n", "y: &r [*r]\n",
    "- " * 300 + "x\n", "include: /etc/passwd\n", "path: /dev/zero\n", "? [a]\n: 1\n",
    "{[1]: 2}", "!!set {a, b}", "!!binary aGk=", "!!omap [a: 1]", "2001-12-14", "!!float .nan",
    "!!python/name:os.system", "---\n", "...\n", "%YAML 1.1\n---\n", "!!bool maybe",
    "!!map 1", "!!seq 1", "!!int x", "!!str [1]", "<<: 1\n"]
GRAMMAR = Lark((GRAMMAR_DIR / "mission.lark").read_text(encoding="utf-8"), parser="lalr",
               lexer="contextual", import_paths=[GRAMMAR_DIR])
BAD_BYTES = [b"\xff", b"\xc3", b"\xe2\x80", b"\xed\xa0\x80", b"\xfe\xff"]


@functools.lru_cache(maxsize=None)
def _shipped(path: str) -> SourceFile:
    """A file of the repository or an installed robot, as its parser counts lines."""
    return _as_source(path)


def _as_source(path: str) -> SourceFile:
    data = Path(path).read_bytes() if Path(path).is_file() else b""
    text = data.decode("utf-8", errors="replace").removeprefix("\ufeff")
    kind = kind_of(path) or MISSION
    return SourceFile(path, editor_lines(text) if kind == MISSION else text, BREAKS[kind])


def assert_located(result, folder: Path) -> None:
    """Every diagnostic renders and lies within its file's lines and columns."""
    for diagnostic in result.diagnostics:
        diagnostic.render()
        diagnostic.to_json()
        diagnostic.to_github()
        assert diagnostic.span is not None, diagnostic.headline()
        path = Path(diagnostic.file)
        source = _as_source(diagnostic.file) if folder in path.parents \
            else _shipped(diagnostic.file)
        span, lines = diagnostic.span, source.line_count
        assert 1 <= span.line <= lines, (diagnostic.headline(), lines)
        assert 1 <= span.column <= len(source.line(span.line)) + 1, diagnostic.headline()


def _mutate(data: bytes, draw, pieces: list[str]) -> bytes:
    """``data`` with 1 to 4 random edits: insert a piece or bad bytes, delete, repeat
    or cut a stretch."""
    for _ in range(draw(st.integers(1, 4))):
        at = draw(st.integers(0, len(data)))
        edit = draw(st.sampled_from(["insert", "insert", "bytes", "delete", "repeat", "cut"]))
        if edit == "insert":
            data = data[:at] + draw(st.sampled_from(pieces)).encode() + data[at:]
        elif edit == "bytes":
            data = data[:at] + draw(st.sampled_from(BAD_BYTES)) + data[at:]
        elif edit == "cut":
            data = data[:at]
        else:
            end = min(len(data), at + draw(st.integers(1, 200)))
            times = draw(st.integers(2, 50)) if edit == "repeat" else 0
            data = data[:at] + data[at:end] * times + data[end:]
    return data


@pytest.fixture(scope="module")
def folder(tmp_path_factory) -> Path:
    """A folder with copies of the missions (so that their imports resolve)."""
    where = tmp_path_factory.mktemp("fuzz")
    for path in MISSIONS:
        shutil.copy(path, where / path.name)
    return where


@FUZZ
@given(text=from_lark(GRAMMAR, explicit={
    "_NL": st.sampled_from(["\n", "\r\n", "\n\n# c\n"]),
    "NAME": st.from_regex(r"\A [A-Za-z_][A-Za-z0-9_]{0,8} \Z"),
    "UNIT": st.sampled_from([" s ", " rad/s ", " m/s^2 ", " deg ", " mm ", " N ", " x "]),
    "NUMBER": st.sampled_from([" 0 ", " 1.5 ", " -2 ", " 1e999 ", " " + "9" * 400 + " "]),
    "STRING": st.sampled_from(['"panda/panda_on_table.yaml"', '"bazar/sophia.yaml"',
                               '"bazar_common.mission"', '"/etc/passwd"', '""', '"\\"x"']),
    "COMMENT": st.sampled_from(["# c", "#\f\v\u2028\x85 odd", "#"])}))
def test_missions_from_the_grammar(folder, text):
    path = folder / "generated.mission"
    path.write_text(text, encoding="utf-8")
    assert_located(check_file(path, cache=CACHE), folder)


@FUZZ
@given(data=st.data())
def test_real_missions_mutated(folder, data):
    original = data.draw(st.sampled_from(MISSIONS))
    path = folder / "mutated.mission"
    path.write_bytes(_mutate(original.read_bytes(), data.draw, PIECES))
    assert_located(check_file(path, cache=CACHE), folder)


@FUZZ
@given(data=st.data())
def test_real_worlds_mutated(folder, data):
    original = data.draw(st.sampled_from(WORLDS))
    world = folder / "world.yaml"
    world.write_bytes(_mutate(original.read_bytes(), data.draw, PIECES + YAML_PIECES))
    (folder / "with_world.mission").write_text(
        f'mission fuzz "a mutated world"\nworld "{world}"\nstate a {{\n'
        "    when elapsed > 1 s -> done\n}\nfinal done\n")
    for model in original.parent.iterdir():
        if model.is_dir() and not (folder / model.name).exists():
            (folder / model.name).symlink_to(model)
    assert_located(check_file(folder / "with_world.mission", cache=WorldCache()), folder)
