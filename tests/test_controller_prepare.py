"""A controller prepared for its next cycle (QPs planned, collision pairs found) computes
exactly what it computes unprepared, and a run prepares it before its first cycle."""

import math

import numpy as np
import pinocchio as pin

from robocop_dsl.control import Controller
from robocop_dsl.runtime import load_mission

from conftest import MISSIONS

GROUP = "bazar_upper_joints"
TOOLS = ("bazar_left_hankamp_tool_object_side", "bazar_right_hankamp_tool_object_side")
PRESSED = ([0.6, 0.25, 0.70], [0.6, -0.25, 0.70])
"""Tool targets 4 cm under the workbench surface [m]: the collision dampers bind."""


def _controller(world):
    controller = Controller(world, GROUP, 0.005, hierarchy="strict")
    controller.add_constraint("joint_kinematic", "limits", GROUP)
    avoid = [controller.add_constraint("collision_avoidance", "bench", "bazar_arms",
                                       other="workbench", influence=0.07),
             controller.add_constraint("collision_avoidance", "arms", "bazar_arms",
                                       other="bazar_arms", influence=0.07)]
    down = pin.rpy.rpyToMatrix(0, math.pi, 0)
    for tool, target in zip(TOOLS, PRESSED):
        controller.add_task("body_pose", tool, tool, target=pin.SE3(down, np.array(target)),
                            gain=5.0).enable()
    return controller, avoid


def _start(world):
    """The arms bent down over the workbench: pairs within influence at once."""
    q = world.initial_configuration()
    q[world.joint_group("bazar_arms").q_indices] = [-0.15, 1.2, 0, -2.0, 0, -1.6, 0,
                                                    0.15, 1.2, 0, -1.4, 0, 1.0, 0]
    return q


def _commands(controller, world, q, cycles=60):
    group = world.joint_group(GROUP)
    q, commands = q.copy(), []
    for _ in range(cycles):
        result = controller.compute(q)
        commands.append(result.velocity)
        q[group.q_indices] += result.velocity * 0.005
    return np.array(commands)


def test_a_prepared_controller_commands_what_an_unprepared_one_does(bazar):
    q = _start(bazar)
    prepared, avoid = _controller(bazar)
    prepared.prepare(q)
    assert sum(constraint.pairs_near for constraint in avoid) > 0
    assert all(task.sample().reference is None for task in prepared.tasks())
    plain, _ = _controller(bazar)
    np.testing.assert_allclose(_commands(prepared, bazar, q), _commands(plain, bazar, q),
                               rtol=0, atol=1e-9)


def test_a_state_compute_refuses_is_left_to_it(bazar):
    controller, _ = _controller(bazar)
    q = _start(bazar)
    q[3] = math.nan
    controller.prepare(q)
    result = controller.compute(q)
    assert result.status == "no_solution"
    assert "not finite" in result.reason
    assert not np.any(result.velocity)


def test_a_run_prepares_its_controller_before_the_first_cycle(monkeypatch):
    """Between the start state's entry and the first cycle, the controller is prepared
    at the start configuration with the start state's tasks enabled."""
    seen = []
    prepare = Controller.prepare

    def spy(self, q, dq=None):
        seen.append((q.copy(), sorted(task.name for task in self.tasks() if task.enabled)))
        prepare(self, q, dq)

    monkeypatch.setattr(Controller, "prepare", spy)
    runner = load_mission(MISSIONS / "pickup.mission").runner()
    runner.start()
    assert len(seen) == 1
    np.testing.assert_array_equal(seen[0][0], runner.q)
    assert seen[0][1] == sorted(t.name for t in runner.controller.tasks() if t.enabled)
    assert seen[0][1] == ["arms", "watch"]
    assert runner.run(duration=0.5).outcome == "stopped"
    assert len(seen) == 1
