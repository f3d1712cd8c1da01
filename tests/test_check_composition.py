"""Checking composite missions: imports, constants, behaviour instances, nested machines
and parallel regions; what the .expected files of the fixtures do not show (hints,
notes, several files)."""

import textwrap
from pathlib import Path

import pytest

from robocop_dsl.compile import WorldCache, check_file
from robocop_dsl.lang import ast

REPO = Path(__file__).resolve().parent.parent
INVALID = REPO / "tests" / "fixtures" / "invalid"
COMPOSITE = REPO / "tests" / "fixtures" / "composite"
CACHE = WorldCache()


@pytest.fixture(autouse=True)
def _in_repository(monkeypatch):
    """Imported files are named relative to the working folder: the repository's."""
    monkeypatch.chdir(REPO)


def _check(name: str):
    return check_file(INVALID / f"{name}.mission", cache=CACHE)


def _only(result, code: str):
    found = [d for d in result.diagnostics if d.code == code]
    assert found, [d.code for d in result.diagnostics]
    return found


def _write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(textwrap.dedent(text).lstrip("\n"))
    return path


def test_the_composite_base_and_its_library_are_clean():
    """The mission the composite fixtures are made from, and its library checked alone."""
    for name in ("base.mission", "common.mission"):
        result = check_file(COMPOSITE / name, cache=CACHE)
        assert result.diagnostics == ()
    assert check_file(COMPOSITE / "base.mission", cache=CACHE).mission is not None


def test_a_problem_in_a_behaviour_names_the_instance_that_exposed_it():
    path = INVALID / "composite_behavior_problem.mission"
    result = check_file(path, cache=CACHE)
    rendered = _only(result, "wrong-dimension")[0].render()
    assert f"= note: in approach(left_tool, pickup_point) at {path}:25:13" in rendered
    assert " 13 |         when tool.reached and tool.position_error < 1 s -> down" in rendered


def test_a_problem_in_an_imported_behaviour_is_reported_in_its_file():
    result = _check("composite_library_behavior_problem")
    diagnostic = _only(result, "unknown-body")[0]
    assert diagnostic.file == "tests/fixtures/invalid/lib/broken_behaviors.mission"
    assert diagnostic.source_line.strip() == "enter { tool.target = curent }"
    assert diagnostic.notes[0].startswith("in settle(left_tool) at ")
    assert diagnostic.notes[0].endswith("composite_library_behavior_problem.mission:7:13")


def test_instances_binding_the_same_values_each_report_the_problem_with_their_note(
        tmp_path):
    """Instances of a behaviour with the same arguments are expanded once: their
    problem is the one of those arguments, with a note naming an instance that binds
    them; an instance with other arguments has the problem of its own."""
    path = _write(tmp_path, "m.mission", """
        mission m "One behaviour, three instances."
        world "bazar/sophia.yaml"
        task left_tool: body_pose(bazar_left_hankamp_tool_object_side) {
            feedback = proportional(gain = 5)
        }
        task arms: joint_position(bazar_arms)
        behavior settle(tool: task) {
            state going {
                when tool.error < 1 mm -> there
            }
            final there
        }
        state first: settle(left_tool) {
            enter { enable left_tool }
            when first.there -> second
        }
        state second: settle(left_tool) {
            when second.there -> third
        }
        state third: settle(arms) {
            when third.there -> done
        }
        final done
        """)
    result = check_file(path, cache=CACHE)
    [mixed] = _only(result, "mixed-error")
    [wrong] = _only(result, "wrong-dimension")
    assert mixed.span.line == wrong.span.line == 9
    assert mixed.notes == (f"in settle(left_tool) at {path}:13:14",)
    assert wrong.notes == (f"in settle(arms) at {path}:20:14",)


def test_nested_instances_give_one_note_each_innermost_first(tmp_path):
    _write(tmp_path, "lib.mission", """
        library lib "Behaviours in behaviours."
        behavior inner(tool: task) {
            state going {
                when tool.position_error < 1 s -> there
            }
            final there
        }
        behavior outer(tool: task) {
            state step: inner(tool) {
                when step.there -> there
            }
            final there
        }
        """)
    path = _write(tmp_path, "m.mission", """
        mission m "Outer instantiates inner."
        world "bazar/sophia.yaml"
        import "lib.mission"
        task left_tool: body_pose(bazar_left_hankamp_tool_object_side) {
            feedback = proportional(gain = 5)
        }
        state go: outer(left_tool) {
            enter { enable left_tool }
            when go.there -> done
        }
        final done
        """)
    diagnostic = _only(check_file(path, cache=CACHE), "wrong-dimension")[0]
    assert Path(diagnostic.file).name == "lib.mission"
    assert [n.split(" at ")[0] for n in diagnostic.notes] == ["in inner(left_tool)",
                                                             "in outer(left_tool)"]
    assert diagnostic.notes[1].endswith("m.mission:7:11")


def test_a_duplicate_across_files_names_the_other_file_and_line():
    result = _check("composite_duplicate_across_imports")
    hints = {d.message: d.hint for d in result.diagnostics}
    assert hints["task or constraint 'left_tool' is already declared"] == \
        "first declared at tests/fixtures/composite/common.mission:18"
    between = _check("composite_duplicate_between_libraries")
    behavior = next(d for d in between.diagnostics if "behavior 'reach'" in d.message)
    assert behavior.file == "tests/fixtures/invalid/lib/right_side.mission"
    assert behavior.hint == "first declared at tests/fixtures/invalid/lib/left_side.mission:9"


def test_a_region_conflict_names_both_regions_and_both_lines():
    conflict = _only(_check("composite_region_conflict"), "region-conflict")[0]
    assert "regions 'left' (line 10) and 'right' (line 18)" in conflict.message
    through = _only(_check("composite_region_conflict_behaviors"), "region-conflict")
    tool = next(d for d in through if "'left_tool'" in d.message)
    assert tool.notes[0].startswith("in approach(left_tool, drop_point, height = 5 cm)")
    assert tool.notes[1].startswith("region 'first' changes it in approach(left_tool, "
                                    "pickup_point)")


def test_leaving_a_nested_machine_hints_at_a_final_and_a_clause_of_the_parent():
    result = _check("composite_leave_nested_machine")
    hints = [d.hint for d in _only(result, "transition-out-of-machine")]
    assert "when carry.NAME -> failed" in hints[0]
    assert "when both.left.NAME -> done" in hints[1]
    assert hints[2].startswith("'over' is in the machine of 'carry'")


def test_an_import_cycle_is_reported_at_the_import_that_closes_it():
    diagnostic = _only(_check("composite_import_cycle"), "import-cycle")[0]
    assert diagnostic.file.endswith("lib/cycle_b.mission")
    assert diagnostic.span.line == 2


def test_a_wrong_constant_is_reported_once_at_its_let():
    result = _check("composite_constant_values")
    assert all(d.span.line < 15 for d in result.diagnostics)
    assert len(result.diagnostics) == len({d.span.line for d in result.diagnostics})


def test_graph_checks_wait_for_imports_without_syntax_errors():
    codes = {d.code for d in _check("composite_library_syntax_error").diagnostics}
    assert "missing-token" in codes and "unreachable-state" not in codes


def test_a_behaviour_no_instance_uses_is_checked_on_its_own():
    result = _check("composite_unused_behavior")
    assert {d.code for d in result.diagnostics} == {"no-final-reachable", "unknown-task",
                                                    "unreachable-state"}
    assert all(d.notes == () for d in result.diagnostics)


def test_instances_are_expanded_with_their_arguments_bound():
    """The graph holds each instance's machine; its states keep the behaviour's spans."""
    result = check_file(COMPOSITE / "base.mission", cache=CACHE)
    graph = result.graph
    assert "both/left/above" in graph and "both/right/down" in graph
    assert graph.nodes["pick/arrived"]["outcome"] == "outcome"
    assert graph.nodes["pick/missed"]["span"].file == "tests/fixtures/composite/common.mission"
    assert result.syntax_tree.first(ast.StateDecl).instance.behavior.text == "go_home"


def test_a_library_checked_alone_reports_its_machine_items_only():
    result = _check("composite_library_alone")
    assert {d.code for d in result.diagnostics} == {"not-in-library"}


def test_every_composite_diagnostic_is_located_in_a_file_it_quotes():
    for path in sorted(INVALID.glob("composite_*.mission")):
        for diagnostic in check_file(path, cache=CACHE).diagnostics:
            assert diagnostic.span is not None and diagnostic.source_line, diagnostic
            assert Path(diagnostic.file).is_file()
