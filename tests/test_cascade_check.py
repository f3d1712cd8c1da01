"""Missions on a world of cascaded controllers: which controller runs each task and
constraint, and the errors when none or several move its subject."""

import textwrap

import pytest

from robocop_dsl.compile import check_file, check_source

from conftest import MISSIONS

BODY = """\
    mission m
    world "bazar/sophia_cascade.yaml"
    {declarations}
    state s {{
        when elapsed > 1 s -> done
    }}
    final done
"""


def check(declarations, controller=""):
    text = textwrap.dedent(BODY.format(declarations=declarations))
    if controller:
        text = text.replace('yaml"\n', f'yaml"\ncontroller {controller}\n', 1)
    return check_source(text, "m.mission")


def codes(result):
    return [(d.code, d.message) for d in result.diagnostics]


def test_pickup_cascade_assigns_each_task_to_the_controller_that_moves_it():
    """Arm tasks and constraints go to the 5 ms controller, the gaze and the head limits
    to the 20 ms one; the fastest runs the state machine."""
    result = check_file(MISSIONS / "pickup_cascade.mission")
    assert result.diagnostics == ()
    spec = result.mission
    assert spec.controllers == ("arms_controller", "head_controller") and spec.cascaded
    assert spec.controller == "arms_controller"
    owners = {n: t.controller for n, t in {**spec.tasks, **spec.constraints}.items()}
    assert owners == {"arms": "arms_controller", "left_tool": "arms_controller",
                      "watch": "head_controller", "arm_limits": "arms_controller",
                      "head_limits": "head_controller", "left_speed": "arms_controller"}


def test_single_controller_missions_are_unchanged():
    """pickup.mission (with its gaze) runs everything on its one controller."""
    result = check_file(MISSIONS / "pickup.mission")
    assert result.diagnostics == ()
    spec = result.mission
    assert spec.controllers == ("whole_body_controller",) and not spec.cascaded
    assert {t.controller for t in spec.tasks.values()} == {"whole_body_controller"}


def test_a_group_spanning_two_controllers_is_an_error():
    """joint_kinematic(bazar_upper_joints) would need both controllers."""
    result = check("constraint limits: joint_kinematic(bazar_upper_joints) "
                   "{ max_velocity = 1 rad/s }")
    assert codes(result) == [(
        "several-controllers", "'bazar_upper_joints' is moved by the joints of several "
        "controllers: arms_controller (bazar_arms), head_controller (bazar_ptu)")]
    assert result.diagnostics[0].span.line == 3


@pytest.mark.parametrize("declaration, subject", [
    ("task hold: body_pose(workbench) { }", "workbench"),
    ("task point: body_position(pickup_point) { }", "pickup_point"),
])
def test_a_subject_no_controller_moves_is_an_error(declaration, subject):
    """A body fixed to the world belongs to no controller."""
    assert codes(check(declaration)) == [("no-controller", f"no controller moves '{subject}'")]


def test_naming_a_controller_runs_that_one_alone():
    """``controller head_controller`` is a single-controller mission: no assignment."""
    result = check("task watch: gaze(kinect2_rgb_optical_frame) { target = part_body }",
                   controller="head_controller")
    assert result.diagnostics == ()
    assert result.mission.controllers == ("head_controller",)


def test_overlapping_controllers_still_need_a_name():
    """Controllers on shared joints cannot run cascaded: the mission must pick one."""
    result = check_file(MISSIONS.parent / "tests/fixtures/invalid/several_controllers.mission")
    assert [d.code for d in result.diagnostics] == ["missing-controller"]
