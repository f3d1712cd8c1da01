"""Syntax errors: labelled with the typical mistake, all of them reported."""

import pytest

from robocop_dsl.lang import parse_mission


def _headlines(text: str) -> list[str]:
    return [d.headline() for d in parse_mission(text, "t.mission").diagnostics]


def _rendered(text: str) -> str:
    return "\n\n".join(d.render() for d in parse_mission(text, "t.mission").diagnostics)


def test_missing_arrow_rendered_exactly():
    """A when clause without '->' names the missing token, with caret and hint."""
    assert _rendered("state a {\n    when b.reached done\n}\n") == (
        "t.mission:2:20: error[missing-token]: missing '->' before name 'done'\n"
        " 2 |     when b.reached done\n"
        "   |                    ^^^^\n"
        "   = hint: a transition is written 'when CONDITION -> STATE'")


def test_missing_closing_brace_rendered_exactly():
    """An unclosed block is found at the next statement that cannot be inside it."""
    assert _rendered("state a {\n    enter { enable t\n    when t.reached -> b\n}\n") == (
        "t.mission:3:5: error[missing-token]: missing '}' before 'when'\n"
        " 3 |     when t.reached -> b\n"
        "   |     ^^^^\n"
        "   = hint: the block opened at line 2 is not closed")


def test_colon_for_equals_rendered_exactly():
    """':' written where '=' belongs."""
    assert _rendered("task t: body_pose(b) {\n    gain: 2\n}\n") == (
        "t.mission:2:9: error[wrong-token]: expected '=' here, not ':'\n"
        " 2 |     gain: 2\n"
        "   |         ^\n"
        "   = hint: a parameter or field is set with 'NAME = VALUE'")


def test_equals_for_colon():
    """'=' written where a declaration's ':' belongs."""
    assert _headlines("task t = body_pose(b)\n") == [
        "t.mission:1:8: error[wrong-token]: expected ':' here, not '='"]


def test_unclosed_block_at_end_of_file():
    """The end of the file closes open blocks once, with one diagnostic."""
    assert _headlines("state a {\n  enter {\n    enable t\n") == [
        "t.mission:3:13: error[missing-token]: missing '}' at the end of the file"]


def test_several_errors_all_reported():
    """Recovery goes on after each error: one diagnostic per broken statement."""
    text = ("task t: body_pose(b) {\n    gain 2\n}\n"
            "state a {\n    when t.reached b\n    when elapsed = 1 s -> b\n"
            "    enter { enable t $ }\n}\n"
            "final b\n")
    assert _headlines(text) == [
        "t.mission:2:10: error[missing-token]: missing '=' before number 2",
        "t.mission:5:20: error[missing-token]: missing '->' before name 'b'",
        "t.mission:6:18: error[syntax-error]: '=' is not a comparison",
        "t.mission:7:22: error[bad-character]: unexpected character '$'",
    ]


def test_what_parsed_around_errors_is_kept():
    """Statements before and after a broken one stay in the tree."""
    result = parse_mission("start a\nstate a {\n  when ->\n}\nfinal b\n")
    assert [type(i).__name__ for i in result.mission.items] == [
        "StartDecl", "StateDecl", "StateDecl"]
    assert len(result.diagnostics) == 1


def test_generic_error_lists_what_was_expected():
    """An unexpected token is shown with the expected ones."""
    diagnostic = parse_mission("state a {\n  when x.reached and -> b\n}\n").diagnostics[0]
    assert diagnostic.message == "unexpected '->'"
    assert diagnostic.hint == ("expected '(', 'clearance', 'distance', 'elapsed', 'event', "
                               "'not', 'time', a name")


def test_unterminated_string():
    """A string left open is named as such."""
    assert _headlines('state a {\n  enter { log "abc }\n}\n') == [
        "t.mission:2:15: error[unterminated-string]: unterminated string"]


def test_reserved_word_used_as_a_name():
    """A statement keyword cannot name a task; the rest still parses."""
    result = parse_mission("task log: body_pose(b)\n", "t.mission")
    assert [d.headline() for d in result.diagnostics] == [
        "t.mission:1:6: error[reserved-word]: 'log' is a reserved word, not a name"]
    assert result.mission.tasks[0].name.text == "log"


def test_missing_bracket_does_not_swallow_the_next_lines():
    """A vector left open ends at the end of its line."""
    assert _headlines("state a {\n  enter {\n    t.target = [1, 2 rad\n    enable t\n"
                      "  }\n}\n") == [
        "t.mission:3:22: error[missing-token]: missing ']' before name 'rad'"]


@pytest.mark.parametrize("text", [
    "}", "{{{{", "state", "state a {", "when", "when -> ->", "task t: (", "[1, 2",
    "mission \"", "))))", "final a: {", "state a { enter { enter { } } }", "->", "\x00",
    "task t: x(y) { a = b offset }", "when not not not -> a", "state a {\n}\n}\n}\n",
])
def test_garbage_never_raises(text):
    """Any input gives diagnostics, never an exception."""
    result = parse_mission(text)
    assert result.diagnostics
    assert all(d.code and d.is_error for d in result.diagnostics)
