"""The shipped missions check clean against their real worlds; checks on small texts."""

from pathlib import Path

import pytest

from robocop_dsl.compile import check_file, check_source
from robocop_dsl.lang import ast

REPO = Path(__file__).resolve().parent.parent
MISSIONS = sorted((REPO / "missions").glob("*.mission"))

HEAD = 'mission m\nworld "bazar/sophia.yaml"\n'


@pytest.mark.parametrize("path", MISSIONS, ids=lambda p: p.name)
def test_mission_checks_without_any_diagnostic(path):
    """No error and no warning: every mission and library in missions/ is clean; a
    mission compiles, a library (declarations only) does not."""
    result = check_file(path)
    assert result.diagnostics == (), [d.render() for d in result.diagnostics]
    library = result.syntax_tree.first(ast.LibraryHeader) is not None
    assert (result.mission is None) == library


def test_the_three_missions_exist():
    """Pick-and-place, a Panda reach and a dual-arm mission ship with the package."""
    assert {p.stem for p in MISSIONS} >= {"pickup", "panda_reach", "dual_arm", "two_parts",
                                          "dual_arm_parallel", "bazar_common"}


def _codes(text: str, world) -> list[str]:
    return [d.code for d in check_source(HEAD + text, "t.mission", world=world).diagnostics]


def test_all_errors_reported_in_one_pass(bazar):
    """Several independent semantic errors all come out."""
    text = ("task a: joint_position(bazar_arm)\ntask b: body_pose(pickup_pont)\n"
            "state s {\n  enter { enable c }\n  when elapsed > 1 rad -> nowhere\n}\nfinal done\n")
    assert _codes(text, bazar) == ["unknown-joint-group", "unknown-body", "dead-end-state",
                                   "no-final-reachable", "unknown-task", "wrong-dimension",
                                   "unknown-state", "unreachable-state"]


def test_scalar_target_for_one_dof_joint(bazar):
    """A single number is a target only for a one-dof group."""
    text = ("task p: joint_position(bazar_ptu) {\n  target = 10 deg\n}\n"
            "state s {\n  enter { enable p }\n  when p.reached -> done\n}\nfinal done\n")
    assert _codes(text, bazar) == ["wrong-length"]


def test_constraint_limits_accept_vectors_per_dof(bazar):
    """Per-dof limits: one number broadcast or one per joint."""
    text = ("constraint c: joint_kinematic(bazar_ptu) {\n  max_velocity = [1, 2] rad/s\n"
            "  min_position = [-10, -10, 0] deg\n}\nstate s {\n  when elapsed > 1 s -> done\n}\n"
            "final done\n")
    assert _codes(text, bazar) == ["wrong-length"]


def test_without_world_the_mission_checks_still_run():
    """A world that cannot be found still lets the mission's own checks run."""
    result = check_source('mission m\nworld "nowhere.yaml"\nstate s {\n  when x.reached -> s\n}\n',
                          "t.mission")
    assert [d.code for d in result.diagnostics] == [
        "world-not-found", "no-final-reachable", "unknown-task"]
    assert result.mission is None


def test_may_be_enabled_follows_disable(bazar):
    """A task disabled on the only path before a state is reported in that state."""
    text = ("task t: body_pose(bazar_left_hankamp_tool_object_side)\n"
            "state a {\n  enter { enable t }\n  exit { disable t }\n  when t.reached -> b\n}\n"
            "state b {\n  when t.reached -> done\n}\nfinal done\n")
    result = check_source(HEAD + text, "t.mission", world=bazar)
    assert [(d.code, d.span.line) for d in result.diagnostics] == [("task-never-enabled", 10)]
