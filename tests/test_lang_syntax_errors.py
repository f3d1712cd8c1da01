"""Syntax errors: labelled with the typical mistake, all of them reported."""

from pathlib import Path

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
    """An unclosed block is reported at its '{', the hint saying where it ends."""
    assert _rendered("state a {\n    enter { enable t\n    when t.reached -> b\n}\n") == (
        "t.mission:2:11: error[missing-token]: missing '}' for this '{'\n"
        " 2 |     enter { enable t\n"
        "   |           ^\n"
        "   = hint: close it before line 3")


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
    """The end of the file closes the open blocks, each reported at its '{'."""
    diagnostics = parse_mission("state a {\n  enter {\n    enable t\n", "t.mission").diagnostics
    assert [d.headline() for d in diagnostics] == [
        "t.mission:1:9: error[missing-token]: missing '}' for this '{'",
        "t.mission:2:9: error[missing-token]: missing '}' for this '{'"]
    assert {d.hint for d in diagnostics} == {"close it at the end of the file"}


PICKUP = (Path(__file__).resolve().parent.parent / "missions" / "pickup.mission").read_text()


def _typed(before: str, *lines: str) -> str:
    """pickup.mission with ``lines`` typed before its line that starts with ``before``."""
    rows = PICKUP.split("\n")
    at = next(i for i, row in enumerate(rows) if row.startswith(before))
    return "\n".join(rows[:at] + list(lines) + rows[at:])


@pytest.mark.parametrize("lines, braces", [
    (["state typing {", "    enter { enable arms", ""], ["66:14", "67:11"]),
    (["state typing {", ""], ["66:14"]),
    (["state typing: reach(pickup_point, 1 mm, 10 s) {", ""], ["66:47"]),
    (["task typing: body_pose(b) {", "    gain = 1", ""], ["66:27"]),
    (["when elapsed > 1 s -> done {", "    emit go", ""], ["66:28"]),
])
def test_an_unclosed_block_while_typing_is_reported_at_its_brace(lines, braces):
    """A block being typed and not closed yet: its '{' is reported, nothing else, and
    the states after it stay at the top of the mission."""
    result = parse_mission(_typed("state grasp", *lines), "t.mission")
    assert [f"{d.span.line}:{d.span.column}" for d in result.diagnostics] == braces
    assert {d.message for d in result.diagnostics} == {"missing '}' for this '{'"}
    states = [s.name.text for s in result.mission.states]
    assert {"grasp", "lift", "release", "done", "failed"} <= set(states)


@pytest.mark.parametrize("lines, expected", [
    (["state typing {", "    when elapsed > ", ""],
     ["66:14 missing '}' for this '{'", "67:20 unexpected end of line"]),
    (["state typing {", "    enter { enable ", ""],
     ["66:14 missing '}' for this '{'", "67:11 missing '}' for this '{'",
      "67:20 unexpected end of line"]),
    (["state typing {", "    when elapsed > "],
     ["66:14 missing '}' for this '{'", "67:20 unexpected end of line"]),
    (["state typing {", "    enter { enable arms, ", ""],
     ["66:14 missing '}' for this '{'", "67:11 missing '}' for this '{'",
      "67:26 unexpected end of line"]),
    (["state typing {", "    when not ", ""],
     ["66:14 missing '}' for this '{'", "67:14 unexpected end of line"]),
    (["state typing {", "    when elapsed > 1 s and", ""],
     ["66:14 missing '}' for this '{'", "67:27 unexpected end of line"]),
])
def test_an_unclosed_block_with_a_line_half_typed_does_not_cascade(lines, expected):
    """A block left open on a statement still being typed: its '{' and the unfinished
    line are reported, nothing else (the closing put after the unfinished line was read
    as its end, and the states after it went into the block)."""
    result = parse_mission(_typed("state grasp", *lines), "t.mission")
    assert [f"{d.span.line}:{d.span.column} {d.message}"
            for d in result.diagnostics] == expected
    states = [s.name.text for s in result.mission.states]
    assert {"grasp", "lift", "release", "done", "failed"} <= set(states)


def test_an_unclosed_block_before_declarations_does_not_cascade():
    """Blocks left open above top-level declarations: the two braces are reported,
    first, and the declarations after them still parse."""
    text = _typed("let home_posture", "state typing {", "  enter {", "")
    result = parse_mission(text, "t.mission")
    assert [d.headline() for d in result.diagnostics] == [
        "t.mission:6:14: error[missing-token]: missing '}' for this '{'",
        "t.mission:7:9: error[missing-token]: missing '}' for this '{'"]
    assert result.diagnostics[0].hint == "close it before line 9"
    assert [t.name.text for t in result.mission.tasks] == ["arms", "left_tool", "watch"]


def test_a_block_closed_by_a_brace_less_indented_than_its_own():
    """The '}' of the outer block ends the inner one too: the inner '{' is the one
    reported."""
    result = parse_mission("state a {\n    enter { enable t\n}\nfinal b\n", "t.mission")
    assert [d.headline() for d in result.diagnostics] == [
        "t.mission:2:11: error[missing-token]: missing '}' for this '{'"]
    assert [s.name.text for s in result.mission.states] == ["a", "b"]


def test_braces_that_cannot_close_where_the_layout_says_stay_reported_in_the_text():
    """A file cut after braces opened one after the other: closing them where the
    layout says does not parse either, and no diagnostic points into the braces that
    were tried."""
    text = (Path(__file__).parent / "fixtures/invalid/var_force_of_wrong_kind.mission"
            ).read_text()
    text = "1e999" + text[:text.index("enter { p") + len("enter { p")] + "{" * 80
    lines = text.split("\n")
    result = parse_mission(text, "t.mission")
    assert result.diagnostics
    assert all(d.span.column <= len(lines[d.span.line - 1]) + 1
               for d in result.diagnostics), [d.headline() for d in result.diagnostics]


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
    assert diagnostic.hint == ("expected '(', 'clearance', 'contact', 'distance', 'elapsed', "
                               "'event', 'force', 'not', ...")


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


@pytest.mark.parametrize("header, broken", [
    ("    state moving {", "    state moving moving {"),
    ("state lift: reach(pickup_point offset [0, 0, carry_height], 2 mm, 10 s) {",
     "state lift: reach(pickup_point offset [0, 0, carry_height], 2 mm, 10 s) ) {"),
    ("task arms: joint_position(bazar_arms) {", "task arms joint_position(bazar_arms) {"),
])
def test_a_block_whose_header_does_not_parse_is_skipped_whole(header, broken):
    """A block whose header has a syntax error is skipped to its matching '}': its
    lines are not read as statements of the block around it (each an 'unexpected'
    error, its '}' closing the outer block early), and everything after it parses."""
    assert header in PICKUP
    result = parse_mission(PICKUP.replace(header, broken, 1), "t.mission")
    line = PICKUP.split("\n").index(header) + 1
    assert result.diagnostics and {d.span.line for d in result.diagnostics} == {line}
    assert {"grasp", "move_to_drop", "release", "done", "failed"} <= \
        {s.name.text for s in result.mission.states}
    assert [b.name.text for b in result.mission.behaviors] == ["reach"]


@pytest.mark.parametrize("header, broken, inner, mistake", [
    ("    state moving {", "    state moving moving {",
     "        enter { left_tool.target = goal }", "        enter { left_tool.target goal }"),
    ("    state moving {", "    stat moving {",
     "        when elapsed > timeout -> late", "        when elapsed > timeout -> -> late"),
    ("behavior reach(goal: target, precision: length, timeout: duration) {",
     "behavior reach(goal: target, precision: length, timeout: duration) x {",
     "        when elapsed > timeout -> late", "        when elapsed > timeout -> -> late"),
])
def test_the_contents_of_a_skipped_block_are_still_read_for_syntax_errors(
        header, broken, inner, mistake):
    """The lines of a block whose header does not parse are parsed after a header of
    its kind (a misspelt keyword's nearest): a syntax error inside is reported at its
    line too, and nothing else is."""
    assert header in PICKUP and inner in PICKUP
    at = PICKUP.index(header)
    text = PICKUP[:at] + PICKUP[at:].replace(header, broken, 1).replace(inner, mistake, 1)
    lines = text.split("\n")
    header_line, inner_line = lines.index(broken) + 1, lines.index(mistake) + 1
    found = {d.span.line for d in parse_mission(text, "t.mission").diagnostics}
    assert found == {header_line, inner_line}
    alone = PICKUP[:at] + PICKUP[at:].replace(header, broken, 1)
    assert {d.span.line for d in parse_mission(alone, "t.mission").diagnostics} == \
        {header_line}


def test_a_brace_inside_an_expression_opens_no_block_and_code_after_a_skipped_block_is_read():
    """A stray '{' with code after it on its line is one error, not a block to skip
    (which would swallow the task's own '}'); the code after a skipped block's '}' on
    the same line is read, its errors reported."""
    stray = parse_mission(PICKUP.replace("proportional(gain = 5)", "proportional(gain = {5)"),
                          "t.mission")
    assert [d.headline() for d in stray.diagnostics] == [
        "t.mission:32:40: error[syntax-error]: unexpected '{'"]
    text = PICKUP.replace("    state moving {", "    state moving moving {", 1).replace(
        "        when elapsed > timeout -> late\n    }",
        "        when elapsed > timeout -> late\n    } final x x", 1)
    assert [d.headline() for d in parse_mission(text, "t.mission").diagnostics][-1] == \
        "t.mission:42:15: error[missing-token]: missing ':' before name 'x'"


@pytest.mark.parametrize("word, keyword", [("enterr", "enter"), ("exits", "exit"),
                                           ("stat", "state")])
def test_a_misspelt_keyword_is_one_word_read_as_the_keyword(word, keyword):
    """A misspelt keyword is reported whole (not as a keyword it starts with and the
    rest), with the keyword as the fix, and read as that keyword: its block parses."""
    text = (f"state a {{\n    {word} {{ enable t }}\n    when elapsed > 1 s -> a\n}}\n"
            if keyword != "state" else f"{word} a {{\n    when elapsed > 1 s -> a\n}}\n")
    result = parse_mission(text, "t.mission")
    column = 1 if keyword == "state" else 5
    assert [(d.span.line, d.span.column, d.span.end_column, d.message, d.hint)
            for d in result.diagnostics] == [
        (1 + (keyword != "state"), column, column + len(word), f"unexpected name '{word}'",
         f"did you mean '{keyword}'?")]
    state = result.mission.states[0]
    assert state.name.text == "a" and [t.target.text for t in state.transitions] == ["a"]


def test_a_word_that_is_no_keyword_skips_its_one_line_block_alone():
    """A statement that starts with a word no keyword is near, followed by a block on
    its line, is one error: the block's '}' does not close the block around it."""
    text = "state a {\n    whenever { enable t }\n    when elapsed > 1 s -> a\n}\nfinal b\n"
    result = parse_mission(text, "t.mission")
    assert [d.headline() for d in result.diagnostics] == [
        "t.mission:2:5: error[syntax-error]: unexpected name 'whenever'"]
    assert [s.name.text for s in result.mission.states] == ["a", "b"]


@pytest.mark.parametrize("line", [
    "    when elapsed > 1 s -> done when elapsed > 2 s -> done",
    "    enter { enable t } when elapsed > 1 s -> done",
])
def test_a_second_statement_on_a_line_in_a_block_is_a_missing_new_line(line):
    """A statement that follows another on its line, inside a block, is a missing new
    line at it, not a '}' missing before it (which would close the block early and make
    its real '}' unexpected)."""
    text = f"state s {{\n{line}\n}}\nfinal done\n"
    result = parse_mission(text, "t.mission")
    column = line.rindex("when") + 1
    assert [d.headline() for d in result.diagnostics] == [
        f"t.mission:2:{column}: error[missing-token]: expected a new line before 'when'"]
    assert [s.name.text for s in result.mission.states] == ["s", "done"]


def test_the_contents_of_a_skipped_block_are_not_blamed_for_the_header_read_in_their_place():
    """A state's body under a header misread as ``enter`` (``enteoing {``): its contents
    were parsed with the header's closing on the line of the block's '}', and the
    closing itself was reported, at a column past the end of that line."""
    text = ("state carry {\n    enteoing {\n        enter { tool.target = point }\n"
            "        when tool.reached -> there\n    }\n    final there\n}\n")
    result = parse_mission(text, "t.mission")
    assert [d.headline() for d in result.diagnostics] == [
        "t.mission:2:5: error[syntax-error]: unexpected name 'enteoing'"]
    lines = text.split("\n")
    assert all(d.span.column <= len(lines[d.span.line - 1]) + 1 for d in result.diagnostics)
