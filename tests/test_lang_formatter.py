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


@pytest.mark.parametrize("written, canonical", [
    ("a - (b - c)", "a - (b - c)"), ("(a - b) - c", "a - b - c"),
    ("a + (b + c)", "a + (b + c)"), ("(a * b) + c", "a * b + c"),
    ("(a + b) * c", "(a + b) * c"), ("a / (b * c)", "a / (b * c)"), ("a / b / c", "a / b / c"),
    ("-x * y", "-x * y"), ("-(x * y)", "-(x * y)"), ("- (x+y)", "-(x + y)"),
    ("- 1 m", "-(1 m)"), ("-1 m", "-1 m"), ("2 * -3 mm", "2 * -3 mm"), ("1 - - 2", "1 - -(2)"),
    ("((x))", "x"), ("2*(1 cm+0.5 cm)", "2 * (1 cm + 0.5 cm)"),
    ("0.002 (m/s)/N * (force(hand).z - -9 N)", "0.002 (m/s)/N * (force(hand).z - -9 N)"),
    ("torque(hand) / (1 m)", "torque(hand) / 1 m"),
    ("hand.position.z-target.position.z + tool.error",
     "hand.position.z - target.position.z + tool.error"),
    ("hand.position - [0, 0, 1] cm", "hand.position - [0, 0, 1] cm"),
    ("-[1, 2, 3] m", "-[1, 2, 3] m"),
    ("distance(a, b) / (time - start)", "distance(a, b) / (time - start)"),
    ("clearance(a, b)*2", "clearance(a, b) * 2"),
])
def test_expression_round_trip(written, canonical):
    """An expression prints with the parentheses its tree needs and no others, and a
    negated number stays negated (``-1`` alone is a number): it reads back the same."""
    tree = parse_mission(f"var v: scalar = {written}\n").mission
    text = format_mission(tree)
    assert text == f"var v: scalar = {canonical}\n"
    assert parse_mission(text).mission == tree


def test_vars_measures_and_log_texts():
    """Vars at the top and in a behaviour, assignments, force, torque and contact
    conditions, comparisons with a var, and log texts with their ``{NAME}`` print in
    canonical form and read back the same."""
    text = ('mission m\nworld "panda/panda_press.yaml"\nvar n : count=0\nvar z: length\n'
            "behavior b(t: task) {\n var since: duration = time\n start s\n"
            "state s { when t.reached and torque( hand )>limit-> f {n=n+1} }\nfinal f\n}\n"
            "state touch { during {z=hand.position.z}\n"
            "when force(hand).z< -9 N or contact(hand,table) -> up { log \"n: {n}, z {z}\" } }\n"
            "state up { when hand.position.z > z -> touch\nwhen elapsed>z_limit->touch }\n")
    parsed = parse_mission(text)
    assert parsed.ok
    tree = parsed.mission
    assert format_mission(tree) == (
        'mission m\n\nworld "panda/panda_press.yaml"\nvar n: count = 0\nvar z: length\n\n'
        "behavior b(t: task) {\n    var since: duration = time\n    start s\n\n"
        "    state s {\n        when t.reached and torque(hand) > limit -> f {\n"
        "            n = n + 1\n        }\n    }\n\n    final f\n}\n\n"
        "state touch {\n    during {\n        z = hand.position.z\n    }\n"
        "    when force(hand).z < -9 N or contact(hand, table) -> up {\n"
        '        log "n: {n}, z {z}"\n    }\n}\n\n'
        "state up {\n    when hand.position.z > z -> touch\n"
        "    when elapsed > z_limit -> touch\n}\n")
    assert parse_mission(format_mission(tree)).mission == tree
