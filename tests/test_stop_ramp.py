"""Stopping a moving robot: whatever ends the run (a final state, the duration, a fault,
a stop request), the braking QP brings the command down to zero as fast as
``max_acceleration`` allows, then the robot holds."""

import numpy as np
import pytest

from conftest import write
from robocop_dsl.runtime import Observer, load_mission

ACCELERATION = 5.0   # [rad/s^2] the mission's joint_kinematic max_acceleration
STEP = 0.005         # [s] BAZAR's control period

MOVING = """
mission moving
world "bazar/sophia.yaml"

var zero: scalar = 0
var x: scalar = 1

constraint limits: joint_kinematic(bazar_upper_joints) {
    max_velocity     = 1 rad/s
    max_acceleration = 5 rad/s^2
}

task arms: joint_position(bazar_arms) {
    interpolator = otg(max_velocity = 1 rad/s, max_acceleration = 4 rad/s^2)
    feedback     = proportional(gain = 10)
}

state swing {
    enter { enable arms
            arms.target = [1, 1, 1, -1, 1, 1, 1, 1, 1, 1, -1, 1, 1, 1] rad }
    when elapsed > 400 ms -> done%s
}
final done
"""


class Commands(Observer):
    """Keeps each cycle's command and mission time, and the end event."""

    wants_tasks = False

    def __init__(self):
        self.commands, self.times, self.end = [], [], None

    def on_cycle(self, record):
        self.commands.append(record.command.copy())
        self.times.append(record.time)

    def on_event(self, event):
        if event.kind == "end":
            self.end = event.data


def run(tmp_path, actions="", stop_at=None, duration=None):
    mission = load_mission(write(tmp_path, "moving.mission", MOVING % actions))
    runner = mission.runner()
    commands = Commands()
    runner.add_observer(commands)
    if stop_at is None:
        return runner.run(duration=duration), commands
    while runner.step():
        if runner.time >= stop_at and runner.outcome is None:
            runner.stop("stopped by the test")
    return runner.finish(), commands


def assert_braked(commands, decided):
    """Every change of command within the acceleration limit; the last command zero;
    from ``decided`` [s] on, every joint's speed comes down by the acceleration limit
    each cycle (or to zero), never up."""
    sent = np.vstack([np.zeros_like(commands.commands[0]), *commands.commands])
    steps = np.abs(np.diff(sent, axis=0)).max(axis=1)
    assert steps.max() <= ACCELERATION * STEP + 1e-9
    assert not sent[-1].any() and commands.end["holding"] is True
    assert commands.end["safety"]["held"] is True
    times = np.array(np.concatenate(([0.0], commands.times)))
    stop = np.abs(sent[times >= decided - 1e-9])
    assert stop[0].max() > 4 * ACCELERATION * STEP   # zero at once would break the limit
    expected = np.maximum(stop[:-1] - ACCELERATION * STEP, 0.0)
    np.testing.assert_allclose(stop[1:], expected, atol=1e-7)


def test_entering_a_final_state_brakes_then_holds(tmp_path):
    result, commands = run(tmp_path)
    assert result.outcome == "success"
    assert result.mission_time > 0.405 and "brought to rest in" in result.message
    assert_braked(commands, 0.405)


def test_the_duration_cap_brakes_then_holds(tmp_path):
    result, commands = run(tmp_path, duration=0.3)
    assert result.outcome == "stopped" and result.final_state == "swing"
    assert_braked(commands, 0.3)


def test_a_fault_while_moving_brakes_then_holds(tmp_path):
    """The clause's second action raises (a division by a var that is zero): outcome
    ``fault``, and the robot still brakes at its limit."""
    actions = (' { log "braking"\n'
               "        x = x / zero }")
    result, commands = run(tmp_path, actions)
    assert result.outcome == "fault"
    assert "action 2 of 'when elapsed > 400 ms -> done' in state 'swing'" in result.message
    assert_braked(commands, 0.405)


def test_a_stop_request_brakes_then_holds(tmp_path):
    result, commands = run(tmp_path, stop_at=0.2)
    assert result.outcome == "interrupted" and result.message.startswith("stopped by the test")
    assert_braked(commands, 0.2)


def test_braking_uses_the_smallest_acceleration_limit(tmp_path):
    """The stop brakes at the stricter of the world's and the mission's limits."""
    mission = load_mission(write(tmp_path, "moving.mission", MOVING % ""))
    runner = mission.runner()
    runner.step()
    limits = runner.controller.limits.max_acceleration
    assert limits.shape == (16,) and np.all(limits <= ACCELERATION)
    runner.controller.constraint("limits").disable()
    runner.step()
    world = np.asarray(runner.controller.joint_group.max_acceleration, dtype=float)
    np.testing.assert_array_equal(runner.controller.limits.max_acceleration, world)


def test_a_non_finite_state_holds_at_once(tmp_path):
    """A robot whose state is not finite cannot be braked: the controller holds it."""
    mission = load_mission(write(tmp_path, "moving.mission", MOVING % ""))
    controller = mission.runner().controller
    q = mission.world.initial_configuration()
    q[0] = np.nan
    result = controller.brake(q)
    assert result.status == "no_solution" and not result.velocity.any()
