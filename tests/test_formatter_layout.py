"""Formatting a mission's text keeps the author's layout where it carries meaning:
blank lines, the rows of vectors, calls and conditions, aligned separators and
comments, blocks of one action on one line; and stays a round trip."""

from pathlib import Path

import pytest

from robocop_dsl.lang import parse_mission
from robocop_dsl.lang.formatter import format_mission, format_source
from robocop_dsl.lang.layout import WIDTH

REPO = Path(__file__).resolve().parent.parent
TEXTS = [path for path in sorted((REPO / "missions").glob("*.mission"))
         + sorted((REPO / "tests" / "fixtures").rglob("*.mission"))
         if parse_mission(path.read_text(encoding="utf-8")).ok]


def formatted(text: str) -> str:
    parsed = parse_mission(text)
    assert parsed.ok, [d.render() for d in parsed.diagnostics]
    return format_source(parsed.mission, text)


@pytest.mark.parametrize("path", TEXTS, ids=lambda p: p.relative_to(REPO).as_posix())
def test_round_trip(path):
    """Every mission and fixture without a syntax error: the formatted text parses to
    an equal tree, and formatting it again changes nothing."""
    text = path.read_text(encoding="utf-8")
    parsed = parse_mission(text)
    out = format_source(parsed.mission, text)
    assert parse_mission(out).mission == parsed.mission
    assert formatted(out) == out


def test_pickup_keeps_its_layout():
    """pickup.mission: the two rows of home_posture, the aligned '=' of its constants,
    its aligned '->' and one-line blocks, its aligned comments."""
    out = formatted((REPO / "missions" / "pickup.mission").read_text()).splitlines()
    assert out[5:9] == ["let home_posture    = [0, 0.25, 0, -2, 0, 0.7, 0,",
                        "                       0, 0.25, 0, -2, 0, 0.7, 0] rad",
                        "let approach_height = 10 cm",
                        "let carry_height    = 15 cm"]
    assert "    max_velocity     = 1 rad/s             # a scalar is broadcast over the dofs" \
        in out
    assert ["    during { arms.gain = 10 }", "    exit   { disable arms }"] == \
        out[out.index("    during { arms.gain = 10 }"):][:2]
    assert "    when grasp.late  -> failed" in out
    assert "    when grasp.there -> lift { attach part_body to " \
           "bazar_left_hankamp_tool_object_side }" in out


def test_blank_lines_kept_one_at_most():
    """A blank line the author put between statements stays (one of several), none is
    kept after '{' or before '}'."""
    text = ("state s {\n\n    enter {\n        enable a\n\n\n        enable b\n    }\n"
            "    when a.reached -> s\n\n    when b.reached -> s\n\n}\n")
    assert formatted(text) == ("state s {\n    enter {\n        enable a\n\n"
                               "        enable b\n    }\n    when a.reached -> s\n\n"
                               "    when b.reached -> s\n}\n")


def test_rows_of_calls_and_conditions():
    """Arguments of a call and operands of 'and' written on several lines keep their
    rows, under the first argument or the condition."""
    text = ("task t: body_pose(b) {\n    interpolator = otg(max_velocity = 1 m/s,\n"
            "        max_acceleration = 2 m/s^2)\n}\n"
            "state s {\n    when t.reached and\n   t.error < 1 mm -> s\n}\n")
    assert formatted(text) == (
        "task t: body_pose(b) {\n    interpolator = otg(max_velocity = 1 m/s,\n"
        "                       max_acceleration = 2 m/s^2)\n}\n"
        "state s {\n    when t.reached and\n         t.error < 1 mm -> s\n}\n")


def test_alignment_is_kept_not_made():
    """Separators and comments aligned by the author stay aligned, further out when the
    code grows; those not aligned get one space (two before a comment)."""
    text = ("state s {\n    when a.reached   -> s  # first\n    when b.error<1mm -> s  # second\n"
            "    when c.reached -> s   # alone\n}\n")
    assert formatted(text) == ("state s {\n    when a.reached      -> s  # first\n"
                               "    when b.error < 1 mm -> s  # second\n"
                               "    when c.reached -> s  # alone\n}\n")


def test_a_comment_set_apart_keeps_its_column_and_no_blank_line_is_added():
    """A trailing comment the author set well apart from its code keeps its column
    (comments far apart often share one), further out only when the code needs it; the
    statements keep the blank lines the author wrote, and get none more."""
    text = ('mission m\nworld "w.yaml"                 # the world\nstart s\n'
            "state s {\n    when elapsed > 1 s -> done    # soon\n}\nfinal done\n")
    assert formatted(text) == text


def test_one_line_block_only_when_it_fits():
    """A block of one action stays on one line when it fits in the width, else it is
    opened; format_mission, which has no source, always opens it."""
    long = "a" * WIDTH
    text = f'state s {{\n    enter {{ log "short" }}\n    exit {{ log "{long}" }}\n}}\n'
    assert formatted(text) == (f'state s {{\n    enter {{ log "short" }}\n    exit {{\n'
                               f'        log "{long}"\n    }}\n}}\n')
    assert 'enter {\n        log "short"\n    }' in format_mission(parse_mission(text).mission)


def test_spaces_in_vectors_aligned_types_and_comment_rows_are_kept():
    """A vector keeps the spaces its author put after '[' and after commas (a matrix's
    columns stay aligned), a comment line between two of its rows stays there, and the
    types of adjacent 'var' declarations stay aligned."""
    text = ('let home = [0,  0.25, 0,    -2,     # left arm\n'
            '            # the right arm\n'
            '            0,  0.25, 0.5,  -2] rad\n'
            'let gains = [ 1.5, -2,\n'
            '             -0.5,  3]\n'
            '\n'
            'var tries:    number   = 0\n'
            'var deadline: duration = 10 s\n'
            'var last: duration\n')
    assert formatted(text) == text
    respelt = formatted(text.replace("[0,  0", "[0.0,  0"))
    assert respelt.splitlines()[0].startswith("let home = [0,  0.25, 0,    -2, ")
    assert formatted("let v = [1,2 ,  3]\n") == "let v = [1, 2,  3]\n"
    between_rows = "let v = [1, 2,\n\n         3, 4]\nlet w = 1\n"
    assert formatted(between_rows) == between_rows


def test_a_vector_that_opens_its_first_row_on_a_new_line_keeps_its_rows_and_comments():
    """Rows that start on the line after '[': each keeps its line and its comment
    (they used to shift up one row, two comments ending on one line), one level deeper
    than the line that opens the vector, and a ']' that begins its own line stays there,
    under that line (the rows went under the '[' and the ']' to the last row)."""
    text = "let v = [   # joints\n    1, 2,   # left\n    3, 4]   # right\nlet w = 1\n"
    assert formatted(text) == text
    closed = "let gains = [\n    1, 2,\n    3, 4\n]\nlet w = 1\n"
    assert formatted(closed) == closed
    assert formatted("let v = [\n  1, 2,\n  3\n  ] rad\n") == "let v = [\n    1, 2,\n    3\n] rad\n"
    assert formatted("let v = [1, 2, 3\n]\n") == "let v = [1, 2, 3\n]\n"
    assert formatted("let v = [1, 2,\n    3, 4\n    ]\n") == "let v = [1, 2,\n         3, 4\n]\n"
    nested = ("state s {\n    enter {\n        t.target = [\n            1, 2\n"
              "        ] rad\n    }\n    when elapsed > 1 s -> done\n}\nfinal done\n")
    assert formatted(nested) == nested
