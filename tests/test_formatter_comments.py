"""Formatting a mission's text keeps every comment, where its reader expects it."""

from pathlib import Path

import pytest

from robocop_dsl.lang import parse_mission
from robocop_dsl.lang.formatter import comments, format_source

REPO = Path(__file__).resolve().parent.parent
MISSIONS = sorted((REPO / "missions").glob("*.mission")) + sorted(
    (REPO / "tests" / "fixtures" / "composite").glob("*.mission"))


def formatted(text: str) -> str:
    parsed = parse_mission(text)
    assert parsed.ok, [d.render() for d in parsed.diagnostics]
    return format_source(parsed.mission, text)


@pytest.mark.parametrize("path", MISSIONS, ids=lambda p: p.name)
def test_round_trip_keeps_comments(path):
    """Every comment survives, in order; the tree is unchanged; formatting is idempotent."""
    text = path.read_text(encoding="utf-8")
    out = formatted(text)
    assert [c.text for c in comments(out)] == [c.text for c in comments(text)]
    assert parse_mission(out).mission == parse_mission(text).mission
    assert formatted(out) == out


def test_missions_have_comments_to_keep():
    """The round trip above is not vacuous: the shipped missions hold comments of both
    kinds."""
    found = [c for path in MISSIONS for c in comments(path.read_text(encoding="utf-8"))]
    assert any(c.after_code for c in found) and any(not c.after_code for c in found)


def test_placement():
    """Own-line comments precede the statement after them (indented like it, or one
    level deeper before a closing brace); comments after code end that statement's
    line; a comment at the end of the file stays last; the blank lines are the
    author's."""
    text = ('# the header\nmission m "d"   # named m\nworld "w.yaml"\n\n'
            "task t : body_pose( b ) {   # the tool\n# its gain\ngain=2.50\n"
            "  # nothing after\n}\n"
            "state s {when t.reached->s}  # loops\n# the end\n")
    assert formatted(text) == (
        '# the header\nmission m "d"  # named m\nworld "w.yaml"\n\n'
        "task t: body_pose(b) {  # the tool\n    # its gain\n    gain = 2.5\n"
        "    # nothing after\n}\n"
        "state s {  # loops\n    when t.reached -> s\n}\n# the end\n")


def test_comment_inside_a_one_line_block_stays_after_its_code():
    """A comment after the first row of a vector opened in a one-line block ends that
    row, not the block's header; one after a block closed on its line ends the header."""
    text = ("mission m\nworld \"w.yaml\"\nstate s {\n"
            "    enter { t.target = [1,  # first\n        2] rad }\n"
            "    during { enable t }  # keep\n}\n")
    out = formatted(text)
    assert out == ("mission m\nworld \"w.yaml\"\nstate s {\n    enter {\n"
                   "        t.target = [1,  # first\n                    2] rad\n    }\n"
                   "    during { enable t }  # keep\n}\n")
    assert formatted(out) == out


def test_hash_in_string_is_no_comment():
    """A ``#`` inside a string is text, not a comment."""
    text = 'mission m "pick #3"  # third\nworld "w.yaml"\nstate s {\n  enter { log "#1" }\n}\n'
    assert [c.text for c in comments(text)] == ["# third"]
    assert formatted(text) == ('mission m "pick #3"  # third\nworld "w.yaml"\n'
                               'state s {\n    enter { log "#1" }\n}\n')


def test_blank_lines_around_comment_groups_kept():
    """A comment set apart by blank lines in a block stays set apart."""
    text = ("mission m\nworld \"w.yaml\"\nstate s {\n    enter { enable t }\n\n"
            "    # leave\n    when t.reached -> s\n}\n")
    assert formatted(text) == ("mission m\nworld \"w.yaml\"\nstate s {\n"
                               "    enter { enable t }\n\n    # leave\n"
                               "    when t.reached -> s\n}\n")


def test_a_comment_before_a_blank_line_and_a_closing_brace_keeps_the_block_indent():
    """A comment line followed by a blank line and '}' is indented like the block's
    statements, and formatting the result changes nothing."""
    text = ("mission m\nworld \"w.yaml\"\nstate s {\n    state a {\n"
            "        when elapsed > 1 s -> f\n# note\n\n    }\n    final f\n}\n")
    out = formatted(text)
    assert "\n        # note\n    }\n" in out
    assert formatted(out) == out


def test_a_tab_before_a_trailing_comment_sets_no_column():
    """Tabs between code and a comment give no column to keep (their width is the
    editor's): the comment goes two spaces after the code, at once and ever after."""
    text = "mission m\nworld \"w.yaml\"\nstate s {\n\texit   { disable arms }\t   # off\n}\n"
    out = formatted(text)
    assert "    exit { disable arms }  # off\n" in out
    assert formatted(out) == out
