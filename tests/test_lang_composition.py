"""Composition in the mission language: constants, imports, behaviours, nested machines,
parallel regions and transition actions, parsed, located, formatted and recovered."""

from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from robocop_dsl.diagnostics import Span
from robocop_dsl.lang import ast, format_mission, parse_mission

REPO = Path(__file__).resolve().parent.parent
MISSIONS = sorted((REPO / "missions").glob("*.mission"))

TWO_PARTS = '''\
mission two_parts "Pick two parts with the left tool, one after the other."
world "bazar/sophia.yaml"
import "bazar_common.mission"            # declarations from another file (below)

let approach_height = 10 cm               # a constant: any value, with its unit
let home = [0, 0.25, 0, -2, 0, 0.7, 0] rad

# A behaviour: a reusable sub-machine with typed parameters and named outcomes.
behavior approach(tool: task, point: body, height: length = approach_height) {
    start above
    state above {
        enter { tool.target = point offset [0, 0, height] }
        when tool.reached and tool.position_error < 2 mm -> down
    }
    state down {
        enter { tool.target = point }
        when tool.reached and tool.position_error < 1 mm -> arrived
    }
    when elapsed > 15 s -> missed         # a behaviour's top-level `when` guards its states
    final arrived                         # outcomes: the finals of its machine
    final missed
}

state pick: approach(left_tool, pickup_point) {     # an instance is a state
    enter { enable left_tool }
    exit  { attach part_body to bazar_left_hankamp_tool_object_side }
    when pick.arrived -> carry
    when pick.missed and pick.visits < 3 -> pick      # re-enter: try again
    when pick.missed -> failed
}

state carry {                              # a compound state: a machine inline
    start up
    state up {
        enter { left_tool.target = pickup_point offset [0, 0, 15] cm }
        when left_tool.reached -> over
    }
    state over {
        enter { left_tool.target = drop_point offset [0, 0, 15] cm }
        when left_tool.reached -> there
    }
    final there
    when carry.there -> put_down { log "over the drop point" }   # a transition action
    when elapsed > 20 s -> failed
}

state both: parallel {                     # regions run side by side in one cycle
    enter { enable right_tool }
    region left: approach(left_tool, drop_point)
    region right: approach(right_tool, pickup_point, height = 5 cm)
    when both.done -> finish               # every region is in a final state
    when both.left.missed or both.right.missed -> failed
    when elapsed > 30 s -> failed
}
'''

LIBRARY = '''\
library bazar_common "Tasks, constants and behaviours shared by the bazar missions."
world "bazar/sophia.yaml"
import "bazar_tasks.mission"

let drop_height = 15 cm
let above_drop = drop_point offset [0, 0, drop_height]
let lowered = [0, 0, -drop_height] cm

event go "the operator says go"

task left_tool: body_pose(bazar_left_hankamp_tool_object_side) {
    feedback = proportional(gain = 5)
}

behavior wait_for(signal: event, limit: duration = 10 s, tool: task, keep: constraint) {
    state waiting {
        when event signal -> got {
            log "got it"
            enable tool, keep
        }
    }
    when elapsed > 10 s -> late
    final got
    final late
}

behavior lift(tool: task, height: length = drop_height, target: target = current) {
    state up {
        enter { tool.target = target offset [0, 0, height] }
        when tool.reached -> lifted
    }
    final lifted
}
'''


def _parse(text: str) -> ast.Mission:
    result = parse_mission(text, "t.mission")
    assert result.diagnostics == (), [d.render() for d in result.diagnostics]
    return result.mission


def _headlines(text: str) -> list[str]:
    return [d.headline() for d in parse_mission(text, "t.mission").diagnostics]


def _n(text: str) -> ast.Name:
    return ast.Name(text)


def _member(owner: str, field: str, region: str | None = None) -> ast.Member:
    return ast.Member(_n(owner), _n(field), _n(region) if region else None)


def _ref(name: str) -> ast.Argument:
    return ast.Argument(None, ast.Reference(_n(name)))


# ---- top-level items -----------------------------------------------------------

def test_let_import_and_library():
    """'let', 'import' and 'library' give their nodes, in source order."""
    mission = _parse('library common "shared"\nimport "other.mission"\n'
                     "let height = 10 cm\nlet spot = drop offset [0, 0, height]\n")
    assert mission.items == (
        ast.LibraryHeader(_n("common"), "shared"),
        ast.Import(ast.String("other.mission")),
        ast.Let(_n("height"), ast.Quantity(10.0, _n("cm"))),
        ast.Let(_n("spot"), ast.Offset(_n("drop"), ast.Vector(
            (0.0, 0.0, ast.NameElement(_n("height")))))))


def test_library_without_description():
    """The library's description is optional."""
    assert _parse("library common\n").items == (ast.LibraryHeader(_n("common")),)


def test_names_inside_vectors():
    """Vector elements may be names, negated with '-'; numbers keep their sign."""
    mission = _parse("let v = [0, -1.5, approach_height, -height] cm\n")
    assert mission.items[0].value == ast.Vector(
        (0.0, -1.5, ast.NameElement(_n("approach_height")),
         ast.NameElement(_n("height"), negative=True)), _n("cm"))


def test_behavior_with_typed_parameters_and_machine():
    """A behaviour's parameters, with keyword kinds and defaults, and its machine."""
    mission = _parse("behavior go(tool: task, c: constraint, e: event, height: length = 5 cm,"
                     " t: target = current) {\n"
                     "    start a\n    state a {\n        when tool.reached -> done\n    }\n"
                     "    when elapsed > 3 s -> done\n    final done\n}\n")
    assert mission.items == (ast.BehaviorDecl(
        _n("go"),
        (ast.BehaviorParam(_n("tool"), _n("task")),
         ast.BehaviorParam(_n("c"), _n("constraint")),
         ast.BehaviorParam(_n("e"), _n("event")),
         ast.BehaviorParam(_n("height"), _n("length"), ast.Quantity(5.0, _n("cm"))),
         ast.BehaviorParam(_n("t"), _n("target"), ast.Reference(_n("current")))),
        ast.Machine((
            ast.StartDecl(_n("a")),
            ast.StateDecl(_n("a"), (ast.Transition(_member("tool", "reached"), _n("done")),)),
            ast.Transition(ast.Comparison(ast.Elapsed(), ">", ast.Quantity(3.0, _n("s"))),
                           _n("done")),
            ast.StateDecl(_n("done"), final=True)))),)


def test_behavior_without_parameters():
    """An empty parameter list is allowed; parameters may span lines."""
    mission = _parse("behavior idle() {\n    final done\n}\n"
                     "behavior wide(\n    a: body,\n    b: body,\n) {\n    final done\n}\n")
    idle, wide = mission.items
    assert idle.parameters == () and idle.machine.states[0].final
    assert [p.name.text for p in wide.parameters] == ["a", "b"]


# ---- states -------------------------------------------------------------------

def test_compound_state():
    """A compound state: own blocks and clauses as parts, nested items in its region."""
    mission = _parse("state carry {\n    start up\n    enter { log \"in\" }\n"
                     "    state up {\n        when t.reached -> there\n    }\n"
                     "    final there\n    when carry.there -> put_down\n}\n")
    enter = ast.ActionBlock("enter", (ast.Log("in"),))
    leave = ast.Transition(_member("carry", "there"), _n("put_down"))
    inner = ast.Machine((
        ast.StartDecl(_n("up")),
        ast.StateDecl(_n("up"), (ast.Transition(_member("t", "reached"), _n("there")),)),
        ast.StateDecl(_n("there"), final=True)))
    assert mission.items == (ast.StateDecl(_n("carry"), (enter, leave),
                                           regions=(ast.Region(None, machine=inner),)),)


def test_state_without_nested_items_has_no_region():
    """A flat state keeps an empty region list, as before."""
    assert _parse("state s {\n    enter { enable t }\n}\n").states[0].regions == ()


def test_nesting_is_arbitrary():
    """Compound and parallel states nest inside each other."""
    mission = _parse("state outer {\n    state middle {\n        state both: parallel {\n"
                     "            region r {\n                state deep {\n"
                     "                    enter { enable t }\n                }\n"
                     "            }\n        }\n    }\n}\n")
    middle = mission.states[0].regions[0].machine.states[0]
    both = middle.regions[0].machine.states[0]
    assert both.parallel and both.regions[0].name == _n("r")
    deep = both.regions[0].machine.states[0]
    assert deep == ast.StateDecl(_n("deep"), (ast.ActionBlock("enter", (ast.Enable((_n("t"),)),)),))


def test_instance_state():
    """'state S: B(ARGS) { ... }': positional then named arguments, own parts."""
    mission = _parse("state pick: approach(left_tool, pickup_point, height = 5 cm) {\n"
                     "    enter { enable left_tool }\n    when pick.arrived -> done\n}\n"
                     "state bare: approach(left_tool, [0, 0, -h] cm)\n")
    pick, bare = mission.states
    assert pick == ast.StateDecl(
        _n("pick"),
        (ast.ActionBlock("enter", (ast.Enable((_n("left_tool"),)),)),
         ast.Transition(_member("pick", "arrived"), _n("done"))),
        instance=ast.Instance(_n("approach"), (
            _ref("left_tool"), _ref("pickup_point"),
            ast.Argument(_n("height"), ast.Quantity(5.0, _n("cm"))))))
    assert bare == ast.StateDecl(_n("bare"), instance=ast.Instance(_n("approach"), (
        _ref("left_tool"),
        ast.Argument(None, ast.Vector((0.0, 0.0, ast.NameElement(_n("h"), negative=True)),
                                      _n("cm"))))))


def test_parallel_state():
    """'state S: parallel { ... }': instance and inline regions, own blocks and clauses."""
    mission = _parse("state both: parallel {\n    enter { enable right_tool }\n"
                     "    region left: approach(left_tool, drop_point)\n"
                     "    region right {\n        start a\n        state a {\n"
                     "            enter { log \"a\" }\n        }\n        final b\n"
                     "        when elapsed > 3 s -> b\n    }\n"
                     "    when both.done -> finish\n}\n")
    left = ast.Region(_n("left"), instance=ast.Instance(
        _n("approach"), (_ref("left_tool"), _ref("drop_point"))))
    right = ast.Region(_n("right"), machine=ast.Machine((
        ast.StartDecl(_n("a")),
        ast.StateDecl(_n("a"), (ast.ActionBlock("enter", (ast.Log("a"),)),)),
        ast.StateDecl(_n("b"), final=True),
        ast.Transition(ast.Comparison(ast.Elapsed(), ">", ast.Quantity(3.0, _n("s"))),
                       _n("b")))))
    assert mission.states == [ast.StateDecl(
        _n("both"),
        (ast.ActionBlock("enter", (ast.Enable((_n("right_tool"),)),)),
         ast.Transition(_member("both", "done"), _n("finish"))),
        parallel=True, regions=(left, right))]
    assert mission.states[0].regions[1].machine.guards[0].target == _n("b")


def test_region_named_done_parses():
    """A region named 'done' is the checker's business, not a syntax error."""
    both = _parse("state both: parallel {\n    region done: idle()\n}\n").states[0]
    assert both.regions == (ast.Region(_n("done"), instance=ast.Instance(_n("idle"))),)


# ---- transitions and conditions ------------------------------------------------

def test_transition_actions():
    """'when C -> S { ACTIONS }' on one line or several, in states and at top level."""
    mission = _parse('state s {\n    when a.reached -> t { log "x"\n        enable a }\n}\n'
                     'when event go -> t {\n    disable a\n    emit done\n}\n'
                     'when b.reached -> t { }\n')
    inner = mission.states[0].transitions[0]
    assert inner == ast.Transition(_member("a", "reached"), _n("t"),
                                   (ast.Log("x"), ast.Enable((_n("a"),))))
    guard, empty = mission.guards
    assert guard.actions == (ast.Disable((_n("a"),)), ast.Emit(_n("done")))
    assert empty == ast.Transition(_member("b", "reached"), _n("t"))


def test_region_member_and_visits():
    """'S.REGION.FINAL' names a region's outcome; 'S.visits' compares like any measure."""
    condition = _parse("when both.left.missed or pick.visits < 3 -> s\n").guards[0].condition
    assert condition == ast.Or((
        _member("both", "missed", "left"),
        ast.Comparison(_member("pick", "visits"), "<", ast.Quantity(3.0))))


# ---- spans ---------------------------------------------------------------------

def test_spans_of_nested_nodes():
    """Nested states, regions, instances and transition actions are located."""
    mission = _parse(TWO_PARTS)
    behavior = mission.first(ast.BehaviorDecl)
    assert behavior.span == Span(9, 1, 22, 2)
    assert behavior.machine.span == Span(9, 78, 22, 2)
    assert behavior.parameters[2].span == Span(9, 44, 9, 76)
    assert behavior.machine.states[0].span == Span(11, 5, 14, 6)
    pick, carry, both = mission.states
    assert pick.instance.span == Span(24, 13, 24, 46)
    region = carry.regions[0]
    assert region.span == region.machine.span == Span(33, 5, 42, 16)
    transition = carry.transitions[0]
    assert transition.span == Span(43, 5, 43, 63)
    assert transition.actions[0].span == Span(43, 36, 43, 61)
    assert both.regions[1].span == Span(50, 5, 50, 68)
    assert both.transitions[1].condition.operands[0].span == Span(52, 10, 52, 26)
    let = mission.first(ast.Let)
    assert let.span == Span(5, 1, 5, 28)


def test_span_of_name_element():
    """A negated name in a vector spans the '-' and the name; the name only itself."""
    element = _parse("let v = [0, -height]\n").items[0].value.values[1]
    assert element.span == Span(1, 13, 1, 20)
    assert element.name.span == Span(1, 14, 1, 20)


# ---- formatting ----------------------------------------------------------------

@pytest.mark.parametrize("text", [TWO_PARTS, LIBRARY], ids=["two_parts", "library"])
def test_design_examples_round_trip(text):
    """The composition examples parse and format back to an equal tree, idempotently."""
    tree = _parse(text)
    formatted = format_mission(tree)
    assert _parse(formatted) == tree
    assert format_mission(_parse(formatted)) == formatted


@pytest.mark.parametrize("path", MISSIONS, ids=lambda p: p.name)
def test_missions_round_trip(path):
    """Every shipped mission round-trips through the formatter."""
    tree = _parse(path.read_text(encoding="utf-8"))
    assert _parse(format_mission(tree)) == tree


def test_canonical_layout_of_composition():
    """Nested machines indent by four spaces; sections are set apart by blank lines."""
    text = ("let v=[0,0,-h]cm\nbehavior b(t:task,h:length=1 cm){final done}\n"
            "state c {when c.done->x{log \"y\"}\nenter{enable t}\nfinal done}\n"
            "state p: parallel { region r: b(t) \n region q { final e } }\n"
            "state i: b(t, h = 2 cm)\n")
    assert format_mission(_parse(text)) == (
        "let v = [0, 0, -h] cm\n\n"
        "behavior b(t: task, h: length = 1 cm) {\n    final done\n}\n\n"
        "state c {\n    final done\n\n    when c.done -> x {\n        log \"y\"\n    }\n"
        "    enter {\n        enable t\n    }\n}\n\n"
        "state p: parallel {\n    region r: b(t)\n    region q {\n        final e\n    }\n}\n\n"
        "state i: b(t, h = 2 cm)\n")


def test_parts_keep_their_order_around_the_machine():
    """Clauses written before blocks stay before them after formatting."""
    text = ("state c {\n    when c.done -> x\n    enter { enable t }\n    final done\n"
            "    exit { disable t }\n}\n")
    tree = _parse(text)
    assert _parse(format_mission(tree)) == tree


# ---- syntax errors -------------------------------------------------------------

def test_errors_inside_nested_states_are_all_reported():
    """Typical mistakes are labelled inside compound states; recovery goes on."""
    text = ("state carry {\n    start up\n    state up {\n"
            "        when left_tool.reached over\n    }\n    state over {\n"
            "        enter { enable t\n        when left_tool.reached -> there\n    }\n"
            "    final there\n}\nfinal put_down\n")
    assert _headlines(text) == [
        "t.mission:4:32: error[missing-token]: missing '->' before name 'over'",
        "t.mission:7:15: error[missing-token]: missing '}' for this '{'"]
    hints = [d.hint for d in parse_mission(text).diagnostics]
    assert hints == ["a transition is written 'when CONDITION -> STATE'",
                     "close it before line 8"]
    mission = parse_mission(text).mission
    assert [s.name.text for s in mission.states] == ["carry", "put_down"]


def test_errors_inside_behaviours_and_regions_are_all_reported():
    """Errors in a behaviour's states and in a parallel state's regions, in order."""
    text = ("behavior approach(tool: task, height: length = 5 cm) {\n"
            "    state above {\n        when elapsed = 3 s -> down\n    }\n"
            "    state down {\n        enter { tool.gain: 3 }\n    }\n    final arrived\n}\n"
            "state both: parallel {\n    region left: approach(a, b\n"
            "    region right {\n        state a { when x.reached b }\n        final b\n"
            "    }\n}\n")
    assert _headlines(text) == [
        "t.mission:3:22: error[syntax-error]: '=' is not a comparison",
        "t.mission:6:26: error[wrong-token]: expected '=' here, not ':'",
        "t.mission:11:31: error[missing-token]: missing ')' before end of line",
        "t.mission:13:34: error[missing-token]: missing '->' before name 'b'"]
    mission = parse_mission(text).mission
    assert [type(i).__name__ for i in mission.items] == ["BehaviorDecl", "StateDecl"]
    assert [r.name.text for r in mission.states[0].regions] == ["left", "right"]


def test_errors_in_composition_declarations():
    """Broken 'let', 'import', 'library' and behaviour headers; the rest still parses."""
    text = ('let = 3\nlet x 3 cm\nimport nope\nlibrary "x"\n'
            "behavior b(x task) {\n    final f\n}\nfinal f\n")
    assert _headlines(text) == [
        "t.mission:1:5: error[syntax-error]: unexpected '='",
        "t.mission:2:7: error[missing-token]: missing '=' before number 3",
        "t.mission:3:8: error[syntax-error]: unexpected name 'nope'",
        "t.mission:4:9: error[syntax-error]: unexpected string \"x\"",
        "t.mission:5:14: error[missing-token]: missing ':' before 'task'"]
    mission = parse_mission(text).mission
    assert [type(i).__name__ for i in mission.items] == ["Let", "BehaviorDecl", "StateDecl"]


@pytest.mark.parametrize("word", ["let", "import", "library", "behavior", "region",
                                  "parallel"])
def test_new_statement_words_are_reserved(word):
    """The composition keywords cannot name a task."""
    assert _headlines(f"task {word}: body_pose(b)\n") == [
        f"t.mission:1:6: error[reserved-word]: '{word}' is a reserved word, not a name"]


_SOUP = ["{", "}", "(", ")", "[", "]", "->", "=", ":", ",", ".", "-", "\n", '"x"',
         "let", "import", "library", "behavior", "region", "parallel", "state", "final",
         "start", "when", "enter", "log", "task", "event", "a", "b.c.d", "1", "cm"]


@settings(max_examples=300, deadline=None, suppress_health_check=list(HealthCheck))
@given(text=st.lists(st.sampled_from(_SOUP), max_size=60).map(" ".join))
def test_composition_token_soup_never_raises(text):
    """Random sequences of composition tokens only ever give diagnostics."""
    result = parse_mission(text)
    assert all(d.code and d.is_error for d in result.diagnostics)
