"""The formatter prints canonical text that parses back to the same tree."""

from pathlib import Path

import pytest

from robocop_dsl.lang import format_mission, parse_file, parse_mission
from robocop_dsl.lang.formatter import format_number

REPO = Path(__file__).resolve().parent.parent
TEXTS = sorted((REPO / "missions").glob("*.mission")) + sorted(
    (REPO / "tests" / "fixtures").glob("*/*.mission"))


@pytest.mark.parametrize("path", TEXTS, ids=lambda p: p.name)
def test_round_trip(path):
    """parse -> format -> parse gives an equal tree; formatting is idempotent."""
    tree = parse_file(path).mission
    text = format_mission(tree)
    again = parse_mission(text)
    assert again.mission == tree
    assert format_mission(again.mission) == text


def test_canonical_layout():
    """Layout, spacing and numbers are normalised; comments are dropped."""
    text = ('mission  m   "d"\nworld "w.yaml"   # the world\n'
            "task t : body_pose( b ) { gain=2.50\nweight = 1e-3 }\n"
            "state s {when ( t.reached or t.error<1mm ) and not t.reached->s}\n"
            "final   f : failure\n")
    assert format_mission(parse_mission(text).mission) == (
        'mission m "d"\n\nworld "w.yaml"\n\n'
        "task t: body_pose(b) {\n    gain   = 2.5\n    weight = 0.001\n}\n\n"
        "state s {\n    when (t.reached or t.error < 1 mm) and not t.reached -> s\n}\n\n"
        "final f: failure\n")


@pytest.mark.parametrize("value, text", [(1.0, "1"), (-0.5, "-0.5"), (1e-6, "1e-06"),
                                         (float("inf"), "1e999"), (2.5e20, "2.5e+20")])
def test_format_number(value, text):
    """Numbers print in their shortest exact form."""
    assert format_number(value) == text
