"""Compiled missions: specs in SI with defaults filled in, and the state graph."""

import math
from pathlib import Path

import pytest

from robocop_dsl.compile import load_mission, to_dot, to_mermaid
from robocop_dsl.compile import spec
from robocop_dsl.diagnostics import DiagnosticError

REPO = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def pickup():
    return load_mission(REPO / "missions" / "pickup.mission")


def test_header_world_and_controller(pickup):
    """The mission knows its world file and controller."""
    assert pickup.name == "pickup"
    assert pickup.world_path == REPO / "robots" / "bazar" / "sophia.yaml"
    assert pickup.controller == "whole_body_controller"
    assert pickup.start == "goto_initial_pose"
    assert pickup.final_states == ["done", "failed"]


def test_task_specs(pickup):
    """Tasks carry their subject, interpolator, feedback and defaults."""
    arms, tool = pickup.tasks["arms"], pickup.tasks["left_tool"]
    assert (arms.type, arms.joint_group, arms.body, arms.dofs) == (
        "joint_position", "bazar_arms", None, 14)
    assert arms.interpolator == spec.InterpolatorSpec(
        "otg", {"max_velocity": (1.0,) * 14, "max_acceleration": (1.0,) * 14})
    assert arms.feedback == spec.FeedbackSpec("proportional", {"gain": 1.0})
    assert (arms.priority, arms.weight, arms.gain) == (1, 1.0, None)
    assert arms.target == spec.CurrentTarget()
    assert (tool.body, tool.reference, tool.dofs, tool.priority) == (
        "bazar_left_hankamp_tool_object_side", "world", 6, 0)
    assert tool.interpolator.parameters == {"max_velocity": (0.2,),
                                            "max_acceleration": (0.5,)}


def test_constraint_specs_take_urdf_defaults(pickup):
    """Unset position limits come from the URDF; scalars are broadcast."""
    limits = pickup.constraints["joint_limits"].parameters
    assert limits["max_velocity"] == (1.0,) * 16
    assert limits["max_acceleration"] == (5.0,) * 16
    assert limits["max_position"][1] == pytest.approx(2.094395)
    speed = pickup.constraints["left_speed"]
    assert speed.body == "bazar_left_hankamp_tool_object_side"
    assert speed.parameters == {"reference": "world", "max_linear": 0.5, "max_angular": 1.0}


def test_actions_in_si(pickup):
    """Targets and offsets are converted to metres and radians, constants and behaviour
    arguments bound where they are used."""
    enter = pickup.states["approach"].enter
    assert enter[0] == spec.EnableAction(("left_tool",), span=enter[0].span)
    moving = pickup.states["approach/moving"].enter
    assert moving[0].target == spec.BodyTarget("pickup_point", (0.0, 0.0, 0.1))
    initial = pickup.states["goto_initial_pose"]
    assert initial.enter[1].target.values[3] == -2.0
    assert initial.during[0] == spec.SetParameterAction("arms", "gain", 10.0,
                                                        span=initial.during[0].span)
    [to_lift] = [t for t in pickup.states["grasp"].transitions if t.target == "lift"]
    assert to_lift.actions == (spec.AttachAction(
        "part_body", "bazar_left_hankamp_tool_object_side", span=None),)


def test_transitions_in_order_then_guards(pickup):
    """A state's own clauses in writing order; the top-level guards on the machine; an
    instance's machine under the state, its parameters bound."""
    transitions = pickup.states["approach"].transitions + pickup.machine.guards
    assert [(t.target, t.guard) for t in transitions] == [
        ("grasp", False), ("failed", False), ("failed", True)]
    assert transitions[0].condition == spec.FinalCondition("approach", "there")
    assert transitions[2].condition == spec.ControllerFailedCondition()
    [machine] = pickup.states["approach"].machines
    assert (machine.path, machine.start, list(machine.states)) == (
        "approach", "moving", ["moving", "there", "late"])
    first = pickup.states["approach/moving"].transitions[0]
    assert first.text == "left_tool.reached and left_tool.position_error < 2 mm"
    assert first.condition == spec.AllCondition((
        spec.ReachedCondition("left_tool"),
        spec.CompareCondition(spec.TaskMeasure("left_tool", "position_error"), "<", 0.002)))
    assert pickup.states["done"].transitions == ()
    assert pickup.states["failed"].outcome == "failure"


def test_state_graph_edges_carry_condition_and_span(pickup):
    """Edges of the networkx graph: condition text, span, clauses."""
    graph = pickup.graph
    assert graph.graph["start"] == "goto_initial_pose"
    edge = graph.edges["goto_initial_pose", "approach"]
    assert edge["condition"] == "arms.reached"
    assert edge["span"].line == 56
    failing = graph.edges["grasp", "failed"]
    assert [c.guard for c in failing["clauses"]] == [False, True]
    assert failing["condition"] == "(grasp.late) or (controller.failed)"
    assert graph.edges["grasp/moving", "grasp/late"]["condition"] == "elapsed > 10 s"
    assert graph.graph["machines"]["grasp"].owner == "grasp"
    assert graph.nodes["failed"] == {"final": True, "outcome": "failure", "start": False,
                                     "span": graph.nodes["failed"]["span"], "kind": "final",
                                     "machine": "", "name": "failed"}
    assert graph.out_degree("done") == 0


def test_units_converted(tmp_path):
    """deg, cm, ms and deg/s become rad, m, s and rad/s."""
    mission = load_mission(REPO / "missions" / "panda_reach.mission")
    assert mission.constraints["limits"].parameters["max_velocity"][0] == \
        pytest.approx(math.pi / 2)
    assert mission.tasks["hand"].feedback == spec.FeedbackSpec(
        "pid", {"kp": 5.0, "ki": 0.1, "kd": 0.0})
    home = mission.states["home"].enter[1].target.values
    assert home[3] == pytest.approx(-135 * math.pi / 180)


def test_load_mission_raises_with_every_diagnostic():
    """A mission with errors raises DiagnosticError carrying all of them."""
    with pytest.raises(DiagnosticError) as raised:
        load_mission(REPO / "tests" / "fixtures" / "invalid" / "several_syntax_errors.mission")
    assert len(raised.value.diagnostics) == 4


def test_graph_drawings(pickup):
    """dot and Mermaid: start and finals marked, guards drawn once."""
    dot = to_dot(pickup.graph, pickup.name)
    assert '"__start" -> "goto_initial_pose";' in dot
    assert '"failed" [shape=doublecircle, color=red];' in dot
    assert '"approach/moving" -> "approach/there" [label="left_tool.reached and ' \
        'left_tool.position_error < 2 mm"];' in dot
    assert dot.count("controller.failed") == 1
    mermaid = to_mermaid(pickup.graph)
    assert mermaid.startswith("stateDiagram-v2\n    [*] --> goto_initial_pose\n")
    assert "approach_moving --> approach_there : left_tool.reached and left_tool.position_error " \
        "#lt; 2 mm\n" in mermaid
    assert "    __any --> failed : controller.failed\n" in mermaid
    assert "    done --> [*]\n" in mermaid
