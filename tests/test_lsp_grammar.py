"""The VS Code extension's TextMate grammar, checked against every mission with
``vscode-textmate`` (the tokenizer VS Code itself uses), and against the language's
reserved words, var kinds and units."""

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest

import robocop_dsl.compile  # noqa: F401  (it imports the checker first)
from robocop_dsl.check.variables import KINDS  # after compile
from robocop_dsl.lang.syntax_errors import RESERVED
from robocop_dsl.lang.units import UNITS

REPO = Path(__file__).resolve().parent.parent
EXTENSION = REPO / "editors" / "vscode"
GRAMMAR = json.loads((EXTENSION / "syntaxes" / "mission.tmLanguage.json").read_text())
MISSIONS = sorted([*(REPO / "missions").glob("*.mission"),
                   *(REPO / "tests" / "fixtures" / "lsp").glob("*.mission")])


def _patterns(group: str, scope: str) -> list[re.Pattern]:
    return [re.compile(p["match"]) for p in GRAMMAR["repository"][group]["patterns"]
            if p.get("name", "").startswith(scope)]


def test_every_reserved_word_is_a_keyword():
    """Each reserved word of the parser, and ``var``, is highlighted as a keyword."""
    patterns = _patterns("keyword", "keyword")
    assert {w for w in {*RESERVED, "var"} if not any(p.fullmatch(w) for p in patterns)} \
        == set()


def test_measures_kinds_and_units():
    """``force``, ``torque`` and ``contact`` before ``(`` are measures; after ``var NAME:``
    every var kind, and after a number every unit of the language, get their scope."""
    measures = _patterns("keyword", "support.function")
    assert all(any(p.match(f"{w}(") for p in measures) for w in ("force", "torque", "contact"))
    declaration = next(re.compile(p["match"]) for p in GRAMMAR["repository"]["declaration"]
                       ["patterns"] if p["match"].startswith("\\b(var)"))
    kinds = {declaration.match(f"var x: {kind}").group(4) for kind in KINDS}
    assert kinds == set(KINDS)
    number = re.compile(GRAMMAR["repository"]["number"]["patterns"][0]["match"])
    assert {u for u in UNITS if number.fullmatch(f"2 {u}").group(2) != u} == set()


@pytest.mark.skipif(shutil.which("npm") is None, reason="needs node and npm")
def test_grammar_tokenizes_every_mission():
    """Comments, strings, keywords, numbers and units of every mission get their
    scopes, and no construct runs past its line (the extension's npm test)."""
    if not (EXTENSION / "node_modules" / "vscode-textmate").is_dir():
        subprocess.run(["npm", "install", "--no-audit", "--no-fund", "--loglevel=error"],
                       cwd=EXTENSION, check=True)
    missions = [str(p) for p in MISSIONS]
    result = subprocess.run(["node", "test/grammar.test.js", *missions], cwd=EXTENSION,
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.splitlines()[-1] == f"{len(missions)} passed, 0 failed"
