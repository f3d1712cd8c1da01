"""The otg interpolator from the language on the real BAZAR world: targets assigned
every cycle, angular limits of body tasks, jerk and target velocity."""

import math
import textwrap

import numpy as np
import pinocchio as pin
import pytest

from robocop_dsl.compile import check_file
from robocop_dsl.runtime import load_mission

HEADER = 'world "bazar/sophia.yaml"\n'
TOOL = "bazar_left_hankamp_tool_object_side"
HOME = "[0, 0.25, 0, -2, 0, 0.7, 0, 0, 0.25, 0, -2, 0, 0.7, 0] rad"
BENT = "[0, 0.5, 0, -1.5, 0, 0.7, 0, 0, 0.5, 0, -1.5, 0, 0.7, 0] rad"


def write(tmp_path, body, name="m"):
    path = tmp_path / f"{name}.mission"
    path.write_text(f"mission {name}\n{HEADER}" + textwrap.dedent(body))
    return path


def run(path, duration=30.0):
    runner = load_mission(path).runner()
    return runner, runner.run(duration=duration)


def text(vector):
    return "[" + ", ".join(f"{value:.9g}" for value in vector) + "]"


def trapezoid_duration(distance, velocity, acceleration):
    """Time [s] of a rest-to-rest move under velocity and acceleration limits."""
    if distance * acceleration <= velocity ** 2:
        return 2 * math.sqrt(distance / acceleration)
    return distance / velocity + velocity / acceleration


def test_joint_target_assigned_every_cycle_is_followed(tmp_path):
    _, result = run(write(tmp_path, f"""
        task arms: joint_position(bazar_arms) {{
            interpolator = otg(max_velocity = 1 rad/s, max_acceleration = 1 rad/s^2)
        }}
        state first {{
            enter {{ enable arms }}
            during {{ arms.target = {HOME} }}
            when elapsed > 1 s -> second
        }}
        state second {{
            during {{ arms.target = {BENT} }}
            when arms.reached -> done
            when elapsed > 20 s -> late
        }}
        final done
        final late: failure
    """))
    assert result.outcome == "success", result.message
    assert result.final_state == "done"


def test_body_target_assigned_every_cycle_is_followed(tmp_path):
    _, result = run(write(tmp_path, """
        task tool: body_pose(bazar_left_hankamp_tool_object_side) {
            interpolator = otg(max_velocity = 0.2 m/s, max_acceleration = 0.5 m/s^2)
            feedback     = proportional(gain = 5)
        }
        state first {
            enter { enable tool }
            during { tool.target = pickup_point offset [0, 0, 15] cm }
            when elapsed > 1 s -> second
        }
        state second {
            during { tool.target = pickup_point offset [0, 0, 10] cm }
            when tool.reached and tool.position_error < 2 mm -> done
            when elapsed > 20 s -> late
        }
        final done
        final late: failure
    """))
    assert result.outcome == "success", result.message
    assert result.final_state == "done"


def _tool_pose(tmp_path):
    runner, _ = run(write(tmp_path, f"""
        task tool: body_pose({TOOL}) {{ }}
        final done
    """, "measure"), duration=1.0)
    controller = runner.controller
    return controller.task("tool").pose(controller.state)


ANGULAR = ", max_angular_velocity = 1 rad/s, max_angular_acceleration = 2 rad/s^2"


@pytest.mark.parametrize("angular", [ANGULAR, ""], ids=["given", "default"])
def test_turn_is_bounded_by_the_angular_limits(tmp_path, angular):
    """1 rad/s and 2 rad/s^2 given, or the defaults when only linear limits are."""
    pose = _tool_pose(tmp_path)
    position = pose.translation + [0, 0, 0.2]
    rpy = pin.rpy.matrixToRpy(pose.rotation @ pin.rpy.rpyToMatrix(0, 0, math.pi / 2))
    _, result = run(write(tmp_path, f"""
        task tool: body_pose({TOOL}) {{
            interpolator = otg(max_velocity = 0.2 m/s, max_acceleration = 0.5 m/s^2{angular})
            feedback     = proportional(gain = 5)
        }}
        state move {{
            enter {{
                enable tool
                tool.target = pose(position = {text(position)} m, rpy = {text(rpy)} rad)
            }}
            when tool.interpolated -> done
            when elapsed > 8 s -> late
        }}
        final done
        final late: failure
    """))
    expected = max(trapezoid_duration(0.2, 0.2, 0.5), trapezoid_duration(math.pi / 2, 1, 2))
    assert result.outcome == "success", result.message
    assert result.transitions[0].time == pytest.approx(expected, abs=0.3)


def test_jerk_and_target_velocity_reach_the_controller(tmp_path):
    runner = load_mission(write(tmp_path, f"""
        task arms: joint_position(bazar_arms) {{
            interpolator = otg(max_velocity = 1 rad/s, max_acceleration = 2 rad/s^2,
                               max_jerk = 20 rad/s^3, target_velocity = 0.1 rad/s)
        }}
        task tool: body_pose({TOOL}) {{
            interpolator = otg(max_velocity = 0.2 m/s, max_acceleration = 0.5 m/s^2,
                               max_jerk = 5 m/s^3, max_angular_jerk = 30 rad/s^3)
        }}
        final done
    """)).runner()
    arms = runner.controller.task("arms").interpolator()
    tool = runner.controller.task("tool").interpolator()
    assert np.allclose(arms.limit("jerk"), 20)
    assert np.allclose(arms.parameters()["target_velocity"], 0.1)
    assert np.allclose(tool.limit("jerk"), [5, 5, 5, 30, 30, 30])
    assert np.allclose(tool.limit("velocity"), [0.2, 0.2, 0.2, 1, 1, 1])
    assert np.allclose(tool.limit("acceleration"), [0.5, 0.5, 0.5, 2, 2, 2])


def test_linear_unit_for_an_angular_limit_is_an_error(tmp_path):
    path = write(tmp_path, f"""
        task tool: body_pose({TOOL}) {{
            interpolator = otg(max_velocity = 0.2 m/s, max_acceleration = 0.5 m/s^2,
                               max_angular_velocity = 0.5 m/s)
        }}
        final done
    """)
    lines = path.read_text().splitlines()
    line = next(i for i, text in enumerate(lines, 1) if "max_angular_velocity" in text)
    column = lines[line - 1].index("m/s)") + 1
    errors = [d for d in check_file(path).diagnostics if d.is_error]
    assert [d.code for d in errors] == ["wrong-dimension"]
    assert (errors[0].span.line, errors[0].span.column) == (line, column)
    assert "angular velocity" in errors[0].message
