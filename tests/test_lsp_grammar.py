"""The VS Code extension's TextMate grammar, checked against every mission with
``vscode-textmate`` (the tokenizer VS Code itself uses), and against the language's
reserved words."""

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from robocop_dsl.lang.syntax_errors import RESERVED

REPO = Path(__file__).resolve().parent.parent
EXTENSION = REPO / "editors" / "vscode"


def test_every_reserved_word_is_a_keyword():
    """Each reserved word of the parser is highlighted as a keyword."""
    grammar = json.loads((EXTENSION / "syntaxes" / "mission.tmLanguage.json").read_text())
    patterns = [re.compile(p["match"]) for p in grammar["repository"]["keyword"]["patterns"]
                if p["name"].startswith("keyword")]
    assert {w for w in RESERVED if not any(p.fullmatch(w) for p in patterns)} == set()


@pytest.mark.skipif(shutil.which("npm") is None, reason="needs node and npm")
def test_grammar_tokenizes_every_mission():
    """Comments, strings, keywords, numbers and units of every mission get their
    scopes, and no construct runs past its line (the extension's npm test)."""
    if not (EXTENSION / "node_modules" / "vscode-textmate").is_dir():
        subprocess.run(["npm", "install", "--no-audit", "--no-fund", "--loglevel=error"],
                       cwd=EXTENSION, check=True)
    missions = sorted(str(p) for p in (REPO / "missions").glob("*.mission"))
    result = subprocess.run(["node", "test/grammar.test.js", *missions], cwd=EXTENSION,
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.splitlines()[-1] == f"{len(missions)} passed, 0 failed"
