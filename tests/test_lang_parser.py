"""Parsing mission text into the syntax tree."""

from pathlib import Path

import pytest

from robocop_dsl.diagnostics import Span
from robocop_dsl.lang import ast, parse_file, parse_mission

REPO = Path(__file__).resolve().parent.parent
MISSIONS = sorted((REPO / "missions").glob("*.mission"))


def _parse(text: str) -> ast.Mission:
    result = parse_mission(text, "t.mission")
    assert result.diagnostics == (), [d.render() for d in result.diagnostics]
    return result.mission


@pytest.mark.parametrize("path", MISSIONS, ids=lambda p: p.name)
def test_real_missions_parse_without_diagnostics(path):
    """Every shipped mission parses cleanly; a library holds behaviours, not states."""
    result = parse_file(path)
    assert result.diagnostics == ()
    assert result.mission.states or result.mission.of_type(ast.BehaviorDecl)


def test_pickup_structure():
    """The pickup mission has its declarations in source order."""
    mission = parse_file(REPO / "missions" / "pickup.mission").mission
    header = mission.first(ast.MissionHeader)
    assert header.name.text == "pickup"
    assert header.description.startswith("Pick the part")
    assert mission.first(ast.WorldDecl).path.text == "bazar/sophia.yaml"
    assert [t.name.text for t in mission.tasks] == ["arms", "left_tool", "watch"]
    assert [c.kind.text for c in mission.constraints] == [
        "joint_kinematic", "body_velocity", "collision_avoidance", "collision_avoidance"]
    assert [s.name.text for s in mission.states] == [
        "goto_initial_pose", "approach", "grasp", "lift", "move_to_drop", "release",
        "return", "done", "failed"]
    failed = mission.states[-1]
    assert failed.final and failed.outcome.text == "failure"
    assert len(mission.guards) == 1


def test_vector_may_span_lines_after_commas():
    """A long target vector continues on the next line after a comma."""
    mission = _parse("state s {\n enter {\n  a.target = [1, 2,\n    3] deg\n }\n}\n")
    assign = mission.states[0].block("enter").actions[0]
    assert assign.value == ast.Vector((1.0, 2.0, 3.0), ast.Name("deg"))


def test_a_closing_bracket_may_start_its_own_line():
    """A vector, a call's arguments and a parenthesised condition may close on a line of
    their own, after comments and blank lines; a ')' in a comment closes nothing."""
    mission = _parse("let v = [1, 2,\n        3  # three\n\n  # note\n] deg\n"
                     "task t: body_pose(b) {\n"
                     "    interpolator = otg(max_velocity = 1 m/s,\n"
                     "                       max_acceleration = 2 m/s^2\n"
                     "    )\n}\n"
                     "when (a.reached and\n      b.reached\n) -> s  # (done)\n"
                     "# not a close )\nlet w = 1\n")
    assert mission.items[0].value == ast.Vector((1.0, 2.0, 3.0), ast.Name("deg"))
    otg = mission.tasks[0].parameters[0].value
    assert [argument.name.text for argument in otg.arguments] == ["max_velocity",
                                                                   "max_acceleration"]
    assert isinstance(mission.guards[0].condition, ast.And)
    assert mission.items[-1].name.text == "w"


def test_condition_may_break_after_and():
    """A condition continues on the next line after 'and'."""
    mission = _parse("when a.reached and\n   b.reached -> s\n")
    assert isinstance(mission.guards[0].condition, ast.And)


def test_condition_precedence():
    """'not' binds tighter than 'and', which binds tighter than 'or'."""
    mission = _parse("when not a.reached and b.error < 1 mm or event go -> s\n")
    condition = mission.guards[0].condition
    assert isinstance(condition, ast.Or)
    first, second = condition.operands
    assert isinstance(first, ast.And) and isinstance(first.operands[0], ast.Not)
    assert second == ast.EventCondition(ast.Name("go"))


def test_comparison_with_units_and_measures():
    """Measures: task fields, elapsed, time and distance."""
    mission = _parse("when elapsed >= 2 s or time < 100 ms or distance(a, b) <= 5 cm "
                     "or t.position_error > 1e-3 -> s\n")
    measures = [c.measure for c in mission.guards[0].condition.operands]
    assert isinstance(measures[0], ast.Elapsed) and isinstance(measures[1], ast.Time)
    assert measures[2] == ast.Distance(ast.Name("a"), ast.Name("b"))
    assert measures[3] == ast.Member(ast.Name("t"), ast.Name("position_error"))
    assert mission.guards[0].condition.operands[3].quantity == ast.Quantity(0.001)


def test_every_action():
    """All actions of the language parse to their nodes."""
    mission = _parse('state s {\n enter {\n  enable a, b\n  disable c\n  reset a\n'
                     '  a.gain = 2\n  attach p to q\n  detach p\n  emit go\n  log "hi \\"x\\""\n'
                     ' }\n}\n')
    actions = mission.states[0].block("enter").actions
    assert [type(a).__name__ for a in actions] == [
        "Enable", "Disable", "Reset", "Assign", "Attach", "Detach", "Emit", "Log"]
    assert actions[0].names == (ast.Name("a"), ast.Name("b"))
    assert actions[-1].text == 'hi "x"'


def test_targets():
    """Target values: body, offset body, pose call, current."""
    mission = _parse("state s {\n enter {\n  t.target = p offset [0, 0, 10] cm\n"
                     "  t.target = pose(position = [1, 2, 3] m, rpy = [0, 90, 0] deg)\n"
                     "  t.target = current\n }\n}\n")
    offset, pose, current = (a.value for a in mission.states[0].block("enter").actions)
    assert offset == ast.Offset(ast.Name("p"), ast.Vector((0.0, 0.0, 10.0), ast.Name("cm")))
    assert [a.name.text for a in pose.arguments] == ["position", "rpy"]
    assert current == ast.Reference(ast.Name("current"))


def test_final_states_and_outcomes():
    """'final NAME' and 'final NAME: failure', with an optional enter block."""
    mission = _parse('final done\nfinal failed: failure {\n enter { log "no" }\n}\n')
    done, failed = mission.states
    assert done.final and done.outcome is None and done.parts == ()
    assert failed.outcome.text == "failure" and failed.block("enter") is not None


def test_world_and_controller_stay_usable_as_names():
    """'world' and 'controller' are keywords only where a declaration starts."""
    mission = _parse("task t: body_pose(b) {\n reference = world\n}\n"
                     "when controller.failed -> s\n")
    assert mission.tasks[0].parameters[0].value == ast.Reference(ast.Name("world"))
    assert mission.guards[0].condition == ast.Member(ast.Name("controller"),
                                                      ast.Name("failed"))


def test_spans_are_one_based_and_exclude_trailing_comments():
    """Spans locate nodes; an item's span stops at its last character."""
    mission = _parse("start go   # the first state\n\nstate go {\n}\n")
    start = mission.items[0]
    assert start.span == Span(1, 1, 1, 9)
    assert start.state.span == Span(1, 7, 1, 9)
    assert mission.states[0].span == Span(3, 1, 4, 2)


def test_spans_do_not_take_part_in_equality():
    """The same mission written differently gives equal trees."""
    assert _parse("start  a\n") == _parse("\n\n  start a # x\n")


def test_empty_and_comment_only_texts():
    """An empty file parses to an empty mission."""
    assert _parse("").items == ()
    assert _parse("# only a comment\n\n").items == ()
