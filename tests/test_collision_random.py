"""Randomised runs with collision avoidance: tools sent to random targets, many under
the table or across the other arm; the smallest distance over every checked pair,
recomputed from the logged joint positions with coal on pinocchio's own collision
model (meshes as meshes), never falls below ``min_distance`` minus 1 mm."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin
import pytest

from robocop_dsl.control import Controller, make_interpolator
from robocop_dsl.world.collisions import checked_pairs

MIN_DISTANCE = 0.02
INFLUENCE = 0.1
TOLERANCE = 1e-3
DOWN = pin.rpy.rpyToMatrix(0, np.pi, 0)


@dataclass
class Scene:
    """A robot, the collision constraints on it and where its tools are sent."""

    world: str
    group: str
    time_step: float
    constraints: tuple
    tools: tuple
    targets: tuple
    """Per tool, the low and high corners of the box targets are drawn from [m]."""


BAZAR = Scene("bazar/sophia.yaml", "bazar_upper_joints", 0.005,
              (("bazar_arms", "workbench"), ("bazar_left_arm", "bazar_right_arm"),
               ("bazar_left_arm", "bazar_left_arm"), ("bazar_right_arm", "bazar_right_arm")),
              ("bazar_left_hankamp_tool_object_side", "bazar_right_hankamp_tool_object_side"),
              (((0.35, -0.45, 0.45), (0.85, 0.45, 1.1)),
               ((0.35, -0.45, 0.45), (0.85, 0.45, 1.1))))
PANDA = Scene("panda/panda_on_table.yaml", "panda_arm", 0.002,
              (("panda_arm", "table"), ("panda_arm", "panda_arm")), ("panda_hand",),
              (((0.2, -0.4, 0.55), (0.7, 0.4, 1.1)),))


def run(world, scene: Scene, hierarchy: str, seed: int, targets: int, cycles: int):
    """Send the tools to ``targets`` random poses in turn, ``cycles`` cycles each.

    Returns the logged configurations and the number of cycles the controller failed.
    """
    rng = np.random.default_rng(seed)
    controller = Controller(world, scene.group, scene.time_step, "proxqp", hierarchy)
    controller.add_constraint("joint_kinematic", "limits", scene.group, max_velocity=1.0,
                              max_acceleration=10.0)
    for index, (first, second) in enumerate(scene.constraints):
        controller.add_constraint("collision_avoidance", f"clear_{index}", first,
                                  other=second, min_distance=MIN_DISTANCE, influence=INFLUENCE,
                                  damping=4.0)
    tasks = []
    for tool in scene.tools:
        task = controller.add_task(
            "body_pose", tool, tool, gain=5.0,
            interpolator=make_interpolator("otg", max_velocity=0.3, max_acceleration=1.0))
        task.enable()
        tasks.append(task)
    q = world.initial_configuration()
    group = controller.state.group
    log, failures = [], 0
    for _ in range(targets):
        for task, (low, high) in zip(tasks, scene.targets):
            task.target = pin.SE3(DOWN, rng.uniform(low, high))
        for _ in range(cycles):
            result = controller.compute(q)
            failures += not result.solved
            q = q.copy()
            q[group.q_indices] += result.velocity * scene.time_step
            log.append(q)
    return log, failures


def smallest_distance(world, scene: Scene, log) -> tuple[float, str]:
    """The smallest distance over the checked pairs and all logged configurations,
    computed by coal on pinocchio's collision model, and the pair it occurs for."""
    model = world.model
    data = model.createData()
    collision_model = pin.buildGeomFromUrdfString(model, world.urdf, pin.GeometryType.COLLISION)
    shapes = {}
    for index, obj in enumerate(collision_model.geometryObjects):
        shapes.setdefault(model.frames[obj.parentFrame].name, []).append(index)
    pairs = sorted({pair for first, second in scene.constraints
                    for pair in checked_pairs(world, first, second)})
    names = []
    for a, b in pairs:
        for i in shapes[a]:
            for j in shapes[b]:
                collision_model.addCollisionPair(pin.CollisionPair(i, j))
                names.append(f"{a} / {b}")
    collision_data = pin.GeometryData(collision_model)
    best, where = np.inf, ""
    for q in log:
        pin.computeDistances(model, data, collision_model, collision_data, q)
        distances = [result.min_distance for result in collision_data.distanceResults]
        index = int(np.argmin(distances))
        if distances[index] < best:
            best, where = distances[index], names[index]
    return best, where


@pytest.mark.parametrize("hierarchy", ["strict", "weighted"])
def test_bazar_arms_stay_clear(bazar, hierarchy):
    log, failures = run(bazar, BAZAR, hierarchy, seed=3, targets=3, cycles=500)
    distance, pair = smallest_distance(bazar, BAZAR, log)
    assert MIN_DISTANCE - TOLERANCE <= distance < INFLUENCE, (distance, pair, failures)


def test_panda_stays_clear_of_its_table(panda):
    log, failures = run(panda, PANDA, "strict", seed=5, targets=3, cycles=800)
    distance, pair = smallest_distance(panda, PANDA, log)
    assert MIN_DISTANCE - TOLERANCE <= distance < INFLUENCE, (distance, pair, failures)
