"""Events raised from outside the mission are declared with ``event NAME "text"``."""

from robocop_dsl.compile import check_source
from robocop_dsl.lang import ast, format_mission, parse_mission

TEXT = '''mission m
world "bazar/sophia.yaml"
event go "the operator confirms"
event go
state wait {
    when event go -> done
}
final done
'''


def test_declaration_parses_and_formats_back():
    parsed = parse_mission(TEXT)
    assert parsed.ok
    [first, second] = parsed.mission.of_type(ast.EventDecl)
    assert (first.name.text, first.description) == ("go", "the operator confirms")
    assert second.description is None
    again = parse_mission(format_mission(parsed.mission))
    assert again.mission == parsed.mission


def test_declared_event_is_known_and_duplicates_are_reported(bazar):
    result = check_source(TEXT, "m.mission", world=bazar)
    assert [(d.code, d.span.line) for d in result.diagnostics] == [("duplicate-name", 4)]
    fixed = check_source(TEXT.replace("event go\n", "", 1), "m.mission", world=bazar)
    assert fixed.ok and fixed.mission.events == frozenset({"go"})


def test_undeclared_event_hint_names_both_ways(bazar):
    result = check_source(TEXT.replace('event go "the operator confirms"\nevent go\n', ""),
                          "m.mission", world=bazar)
    [d] = result.diagnostics
    assert d.code == "unknown-event"
    assert d.hint == ("no action emits it: add 'emit go' to a state, or declare 'event go' "
                      "when it comes from outside the mission")
