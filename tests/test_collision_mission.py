"""``collision_avoidance(A, B)`` and ``clearance(A, B)`` in missions: checked, compiled and
run as a user does."""

import subprocess
import sys
from pathlib import Path

from types import SimpleNamespace

import numpy as np
import pytest

from robocop_dsl.runtime import load_mission, read_events, read_timeseries
from robocop_dsl.world.collision_scene import CollisionScene
from robocop_dsl.world.collisions import checked_pairs

REPO = Path(__file__).resolve().parent.parent
HEADER = 'mission m\nworld "bazar/sophia.yaml"\ncontroller whole_body_controller\n'


def robocop(*args):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", *map(str, args)],
                          capture_output=True, text=True, cwd=REPO)


def test_through_the_table_stops_above_and_says_why(tmp_path):
    done = robocop("run", "missions/through_the_table.mission", "--log", tmp_path / "log")
    assert done.returncode == 0, done.stdout + done.stderr
    assert "outcome: success  final state: stopped_above" in done.stdout
    assert "log: the workbench is in the way" in done.stderr
    assert "QP failures: 0" in done.stdout


def test_the_tool_is_held_at_min_distance_above_the_workbench(bazar):
    mission = load_mission(REPO / "missions" / "through_the_table.mission", world=bazar)
    runner = mission.runner()
    result = runner.run(duration=30.0)
    assert result.outcome == "success", result.message
    kinematics = runner.kinematics
    scene = CollisionScene(kinematics.world,
                           checked_pairs(kinematics.world, "bazar_arms", "workbench"))
    scene.place(kinematics)
    assert 0.02 - 1e-3 <= scene.clearance() < 0.025
    tool = kinematics.body_pose("bazar_left_hankamp_tool_object_side").translation
    surface = 0.74
    assert tool[2] > surface + 0.02
    target = kinematics.body_pose("pickup_point").translation + np.array([0, 0, -0.15])
    assert tool[2] - target[2] > 0.15


PUSH = HEADER + """
let under_the_surface = pickup_point offset [0, 0, -12] cm
constraint joint_limits: joint_kinematic(bazar_upper_joints) {
    max_velocity     = 1 rad/s
    max_acceleration = 5 rad/s^2
}
constraint keep_off_the_workbench: collision_avoidance(bazar_arms, workbench) {
    min_distance = 1 cm
    influence    = 10 cm
    damping      = 4
}
task left_tool: body_pose(bazar_left_hankamp_tool_object_side) {
    interpolator = otg(max_velocity = 0.2 m/s, max_acceleration = 0.5 m/s^2)
    feedback     = proportional(gain = 5)
}
state reach {
    enter { enable left_tool
            left_tool.target = under_the_surface }
    when left_tool.reached -> went_through
    when elapsed > 8 s -> held
}
final held
final went_through: failure
"""


def test_a_push_under_the_workbench_is_held_at_min_distance(tmp_path, bazar):
    """The tool pushed 12 cm under the surface with ``min_distance = 1 cm`` and no
    ``controller.failed`` clause: the state times out (success), nothing is relaxed, and
    coal on the logged joint positions finds the arms never closer than 9 mm to the
    workbench and held within a few millimetres of ``min_distance`` at the end."""
    from test_collision_random import smallest_distance

    path = tmp_path / "push.mission"
    path.write_text(PUSH)
    done = robocop("run", path, "--log", tmp_path / "log")
    assert done.returncode == 0, done.stdout + done.stderr
    assert "outcome: success  final state: held" in done.stdout
    kinds = {event["kind"] for event in read_events(tmp_path / "log")}
    assert not kinds & {"constraint_relaxed", "solver_budget", "qp_failure", "fault"}
    series = read_timeseries(tmp_path / "log")
    group = bazar.joint_group("bazar_upper_joints")
    log = []
    for row in range(len(series["time"])):
        q = bazar.initial_configuration()
        q[group.q_indices] = [series[f"q.{joint}"][row] for joint in group.joints]
        log.append(q)
    scene = SimpleNamespace(constraints=(("bazar_arms", "workbench"),))
    closest, _ = smallest_distance(bazar, scene, log)
    final, _ = smallest_distance(bazar, scene, log[-1:])
    assert closest >= 0.01 - 1e-3, closest
    assert final < 0.015, final


@pytest.mark.parametrize("body, code, line, column", [
    ("constraint c: collision_avoidance(bazar_arms)\n", "wrong-arguments", 4, 15),
    ("constraint c: collision_avoidance(bazar_arms, pickup_point)\n", "no-collision-geometry",
     4, 47),
    ("constraint c: collision_avoidance(bazar_arm, workbench)\n", "unknown-body", 4, 35),
    ("constraint c: collision_avoidance(bazar_arms, workbench) {\n"
     "    min_distance = 5 cm\n    influence = 3 cm\n}\n", "wrong-value", 6, 17),
    ("constraint c: collision_avoidance(bazar_arms, workbench) { damping = 2 m }\n",
     "wrong-dimension", 4, 72),
])
def test_collision_declarations_are_checked(tmp_path, body, code, line, column):
    path = tmp_path / "m.mission"
    path.write_text(HEADER + body + "state s { when elapsed > 1 s -> done }\nfinal done\n")
    done = robocop("check", path)
    assert done.returncode == 1
    assert f"m.mission:{line}:{column}: error[{code}]" in done.stdout, done.stdout
    assert "Traceback" not in done.stdout + done.stderr


def test_a_pair_closer_than_min_distance_at_the_start_is_a_warning(tmp_path):
    path = tmp_path / "m.mission"
    path.write_text(HEADER + "constraint own: collision_avoidance(bazar_left_arm, "
                    "bazar_left_arm) {\n    min_distance = 10 cm\n    influence = 20 cm\n}\n"
                    "state s { when elapsed > 1 s -> done }\nfinal done\n")
    done = robocop("check", path)
    assert done.returncode == 0
    assert ("m.mission:4:12: warning[collision-at-start]: 'bazar_left_link_5' and "
            "'bazar_left_hankamp_tool_robot_side' are 7.96 cm apart in the initial posture, "
            "closer than min_distance (10 cm)") in done.stdout


@pytest.mark.parametrize("condition, code", [
    ("clearance(bazar_arms, drop_point) < 1 cm", "no-collision-geometry"),
    ("clearance(bazar_arms, wrkbench) < 1 cm", "unknown-body"),
    ("clearance(bazar_arms, workbench) < 1 s", "wrong-dimension"),
])
def test_clearance_conditions_are_checked(tmp_path, condition, code):
    path = tmp_path / "m.mission"
    path.write_text(HEADER + f"state s {{ when {condition} -> done }}\nfinal done\n")
    done = robocop("check", path)
    assert done.returncode == 1 and f"error[{code}]" in done.stdout, done.stdout


def test_clearance_reads_the_geometry_at_the_current_state(tmp_path, bazar):
    path = tmp_path / "m.mission"
    path.write_text(HEADER + "state s {\n    when clearance(bazar_left_arm, bazar_left_arm) "
                    "< 8 cm -> close\n    when elapsed > 10 ms -> far\n}\n"
                    "final close\nfinal far: failure\n")
    result = load_mission(path, world=bazar).runner().run(duration=1.0)
    assert result.outcome == "success" and result.final_state == "close", result.message


def test_a_cascade_runs_the_constraint_on_its_controller_world_copy(tmp_path):
    text = (REPO / "missions" / "through_the_table.mission").read_text()
    text = text.replace('world "bazar/sophia.yaml"\ncontroller whole_body_controller',
                        'world "bazar/sophia_cascade.yaml"')
    text = text.replace("joint_kinematic(bazar_upper_joints)", "joint_kinematic(bazar_arms)")
    path = tmp_path / "cascade.mission"
    path.write_text(text)
    done = robocop("run", path)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "final state: stopped_above" in done.stdout
