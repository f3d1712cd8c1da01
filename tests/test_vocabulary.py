"""The language's settings run on the real BAZAR world: `reached` against `interpolated`
and the tolerance, tasks enabled from the start and constraints disabled until enabled,
per-axis body velocity limits, per-dof gains in declarations and actions."""

import math
import textwrap

import numpy as np
import pytest

from robocop_dsl.runtime import load_mission

HEADER = 'world "bazar/sophia.yaml"\n'
TOOL = "bazar_left_hankamp_tool_object_side"
HOME = "[0, 0.25, 0, -2, 0, 0.7, 0, 0, 0.25, 0, -2, 0, 0.7, 0] rad"
HOME_VALUES = np.array([0, 0.25, 0, -2, 0, 0.7, 0] * 2)
HALF_DEGREE = math.radians(0.5)


def write(tmp_path, body, name="m"):
    path = tmp_path / f"{name}.mission"
    path.write_text(f"mission {name}\n{HEADER}" + textwrap.dedent(body))
    return path


def step_until(runner, condition, limit=20000):
    """Step ``runner`` until ``condition(runner)`` holds after a cycle; the cycles run."""
    for cycle in range(1, limit + 1):
        running = runner.step()
        if condition(runner):
            return cycle
        assert running, f"the run ended first: {runner.finish().message}"
    raise AssertionError("the condition never held")


def arms_mission(tmp_path, flag, interpolator, extra="", name="m", limit=""):
    """The arms to HOME, ending when ``arms.FLAG`` holds; ``extra`` is one more line of
    the task, ``limit`` the arms' velocity limit (none when empty)."""
    constraint = (f"constraint slow: joint_kinematic(bazar_arms) {{ max_velocity = {limit} }}"
                  if limit else "")
    return write(tmp_path, f"""
        {constraint}
        task arms: joint_position(bazar_arms) {{
            interpolator = {interpolator}
            feedback     = proportional(gain = 1)
            {extra}
        }}
        state moving {{
            enter {{
                enable arms
                arms.target = {HOME}
            }}
            when arms.{flag} -> there
            when elapsed > 30 s -> late
        }}
        final there
        final late: failure
    """, name)


def _arrival(path):
    """The mission time [s] and the arms' joint errors [rad] in the cycle the clause
    fired."""
    runner = load_mission(path).runner()
    step_until(runner, lambda r: r.state == "there")
    arms = runner.controller.task("arms")
    return runner.time, np.abs(arms.error_vector())


def test_reached_waits_for_the_tolerance_with_no_interpolator(tmp_path):
    """With `interpolator = none` the trajectory is over at once: `interpolated` fires
    in the first cycle, `reached` only once every joint is within 0.5 deg."""
    early, far = _arrival(arms_mission(tmp_path, "interpolated", "none", name="a"))
    late, near = _arrival(arms_mission(tmp_path, "reached", "none", name="b"))
    assert early < 0.02 and far.max() > math.radians(20)
    assert late > 2.0
    assert near.max() <= HALF_DEGREE and near.max() > 0.5 * HALF_DEGREE


def test_reached_after_otg_is_within_a_given_tolerance(tmp_path):
    """Arms held back by a velocity limit below the trajectory's end it with degrees of
    error left: `reached` waits for the declared tolerance, one number per joint."""
    otg = "otg(max_velocity = 1 rad/s, max_acceleration = 1 rad/s^2)"
    extra = "tolerance = [0.2, 0.2, 0.2, 0.2, 0.2, 0.2, 0.2, 1, 1, 1, 1, 1, 1, 1] deg"
    ended, left = _arrival(arms_mission(tmp_path, "interpolated", otg, extra, "a",
                                        "0.3 rad/s"))
    arrived, error = _arrival(arms_mission(tmp_path, "reached", otg, extra, "b",
                                           "0.3 rad/s"))
    assert left.max() > math.radians(5)
    assert arrived > ended + 1.0
    assert error[:7].max() <= math.radians(0.2) and error[7:].max() <= math.radians(1)


def test_body_pose_reached_within_both_parts(tmp_path):
    """`pose(position = ..., orientation = ...)` bounds the position and the orientation
    error separately; one number of a dimension sets that part only."""
    mission = load_mission(write(tmp_path, f"""
        task tool: body_pose({TOOL}) {{
            interpolator = otg(max_velocity = 0.2 m/s, max_acceleration = 0.5 m/s^2)
            feedback     = proportional(gain = 2)
            tolerance    = pose(position = 4 mm, orientation = 3 deg)
        }}
        task other: body_pose(bazar_right_hankamp_tool_object_side) {{ tolerance = 2 mm }}
        state moving {{
            enter {{
                enable tool
                tool.target = pickup_point offset [0, 0, 10] cm
            }}
            when tool.reached -> there
            when elapsed > 30 s -> late
        }}
        final there
        final late: failure
    """))
    assert mission.spec.tasks["tool"].tolerance == pytest.approx((0.004, math.radians(3)))
    assert mission.spec.tasks["other"].tolerance == pytest.approx((0.002, math.radians(1)))
    runner = mission.runner()
    step_until(runner, lambda r: r.state == "there")
    tool = runner.controller.task("tool")
    assert tool.interpolated
    assert tool.position_error <= 0.004 and tool.orientation_error <= math.radians(3)


def test_task_enabled_from_the_start_and_constraint_enabled_later(tmp_path):
    """`enabled = true` makes a task active before any state enables it; `enabled =
    false` keeps a constraint off until a state enables it."""
    runner = load_mission(write(tmp_path, f"""
        constraint slow: joint_kinematic(bazar_arms) {{
            max_velocity = 0.05 rad/s
            enabled      = false
        }}
        task arms: joint_position(bazar_arms) {{
            target       = {HOME}
            feedback     = proportional(gain = 2)
            enabled      = true
        }}
        state fast {{
            when elapsed > 0.5 s -> slow
        }}
        state slow {{
            enter {{ enable slow }}
            when elapsed > 1 s -> done
        }}
        final done
    """)).runner()
    assert runner.controller.task("arms").enabled
    assert not runner.controller.constraint("slow").enabled
    speeds = {"fast": [], "slow": []}

    def record(r):
        if r.state in speeds and r.controller.result is not None:
            speeds[r.state].append(np.abs(r.controller.result.velocity).max())
        return r.state == "done"

    step_until(runner, record)
    assert max(speeds["fast"]) > 0.5
    assert max(speeds["slow"][1:]) <= 0.05 + 1e-9


def _tool_velocity(runner) -> np.ndarray:
    """The tool's linear velocity [m/s] in the world frame under the last command."""
    state = runner.controller.state
    jacobian = state.jacobian(state.body(TOOL), 0)[:3]
    return jacobian @ runner.controller.result.velocity


def _tool_position(tmp_path) -> np.ndarray:
    """The tool's position [m] in the world at the initial configuration."""
    runner = load_mission(write(tmp_path, f"""
        task tool: body_position({TOOL}) {{ }}
        state s {{ when elapsed > 1 s -> done }}
        final done
    """, "measure")).runner()
    runner.step()
    return runner.controller.task("tool").compute_value(runner.controller.state).copy()


def test_per_axis_body_velocity_limit(tmp_path):
    """A 3-vector `max_linear` bounds each axis of the reference: the tool goes down
    at 2 cm/s at most while it moves sideways faster."""
    goal = _tool_position(tmp_path) + [0.1, 0.1, -0.05]
    runner = load_mission(write(tmp_path, f"""
        constraint tool_speed: body_velocity({TOOL}) {{
            reference   = world
            max_linear  = [30, 30, 2] cm/s
            max_angular = [1, 1, 1] rad/s
        }}
        task tool: body_position({TOOL}) {{
            interpolator = otg(max_velocity = 0.2 m/s, max_acceleration = 1 m/s^2)
            feedback     = proportional(gain = 2)
        }}
        state moving {{
            enter {{
                enable tool
                tool.target = [{", ".join(f"{v:.9g}" for v in goal)}] m
            }}
            when tool.reached -> done
            when elapsed > 30 s -> late
        }}
        final done
        final late: failure
    """)).runner()
    velocities = []

    def record(r):
        if r.controller.result is not None and r.state == "moving":
            velocities.append(_tool_velocity(r))
        return r.state != "moving"

    step_until(runner, record)
    assert runner.state == "done"
    velocities = np.array(velocities)
    assert np.abs(velocities[:, 2]).max() <= 0.02 + 1e-6
    assert np.abs(velocities[:, 2]).max() > 0.019
    assert np.abs(velocities[:, :2]).max() > 0.03


def test_per_dof_gains_in_declaration_and_action(tmp_path):
    """A gain per joint: the left arm's zero gain holds it while the right one moves;
    `arms.gain = [...]` in a later state swaps them."""
    zeros, twos = ", ".join(["0"] * 7), ", ".join(["2"] * 7)
    runner = load_mission(write(tmp_path, f"""
        task arms: joint_position(bazar_arms) {{
            target   = {HOME}
            gain     = [{zeros}, {twos}]
            enabled  = true
        }}
        state right_first {{
            when elapsed > 1 s -> left_next
        }}
        state left_next {{
            enter {{ arms.gain = [{twos}, {zeros}] }}
            when elapsed > 1 s -> done
        }}
        final done
    """)).runner()
    arms = runner.controller.task("arms")
    start = None

    def errors(r):
        return np.abs(r.controller.task("arms").error_vector())

    step_until(runner, lambda r: r.state == "right_first")
    start = errors(runner)
    step_until(runner, lambda r: r.state == "left_next")
    middle = errors(runner)
    assert middle[:7] == pytest.approx(start[:7], abs=1e-9)
    assert middle[7:].max() < 0.2 * start[7:].max()
    step_until(runner, lambda r: r.state == "done")
    end = errors(runner)
    assert end[:7].max() < 0.2 * start[:7].max()
    assert end[7:] == pytest.approx(middle[7:], abs=1e-3)
    assert arms.gain == pytest.approx([2] * 7 + [0] * 7)
