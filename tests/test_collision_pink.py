"""The collision_avoidance constraint against Pink's SelfCollisionBarrier on the same
scene: the same QP objective with Pink's barrier rows (pinocchio's own collision model,
joint Jacobians) in place of ours gives the same command to 1e-6."""

import numpy as np
import pinocchio as pin
import pytest

from robocop_dsl.control import Controller, make_interpolator
from robocop_dsl.control.solvers.portable import portable_proxsuite
from robocop_dsl.world.collisions import checked_pairs

proxsuite = portable_proxsuite()
TOOL = "bazar_left_hankamp_tool_object_side"
MIN_DISTANCE, INFLUENCE, DAMPING = 0.02, 0.12, 3.0


def _controller(world, hierarchy):
    controller = Controller(world, "bazar_upper_joints", 0.005, "proxqp", hierarchy)
    controller.add_constraint("joint_kinematic", "limits", "bazar_upper_joints")
    constraint = controller.add_constraint(
        "collision_avoidance", "clear", "bazar_arms", other="workbench",
        min_distance=MIN_DISTANCE, influence=INFLUENCE, damping=DAMPING)
    return controller, constraint


def _near_table(world):
    """A posture with the left tool a few centimetres above the workbench, pointing down."""
    controller = Controller(world, "bazar_upper_joints", 0.005, "proxqp", "weighted")
    controller.add_constraint("joint_kinematic", "limits", "bazar_upper_joints")
    target = pin.SE3(pin.rpy.rpyToMatrix(0, np.pi, 0), np.array([0.55, 0.25, 0.86]))
    task = controller.add_task("body_pose", "tool", TOOL, target=target, gain=5.0,
                               interpolator=make_interpolator("otg", max_velocity=0.5,
                                                              max_acceleration=2.0))
    task.enable()
    q = world.initial_configuration()
    group = controller.state.group
    while not task.reached:
        q[group.q_indices] += controller.compute(q).velocity * controller.time_step
    return q


def _pink_rows(world, q, count):
    """Pink's barrier rows ``J v >= -h`` over the pairs of the constraint."""
    from pink import Configuration
    from pink.barriers import SelfCollisionBarrier

    collision_model = pin.GeometryModel(world.collision_model)
    names = [obj.name for obj in collision_model.geometryObjects]
    for first, second in checked_pairs(world, "bazar_arms", "workbench"):
        collision_model.addCollisionPair(pin.CollisionPair(
            names.index(f"{first}_0"), names.index(f"{second}_0")))
    model = world.model
    configuration = Configuration(model, model.createData(), q,
                                  collision_model=collision_model)
    barrier = SelfCollisionBarrier(count, gain=DAMPING, safe_displacement_gain=0.0,
                                   d_min=MIN_DISTANCE)
    dt = 0.005
    G, h = barrier.compute_qp_inequalities(configuration, dt)
    columns = world.joint_group("bazar_upper_joints").v_indices
    return -G[:, columns] * dt, -h


@pytest.mark.parametrize("hierarchy", ["weighted", "strict"])
def test_command_matches_pink_barrier(bazar, hierarchy):
    q = _near_table(bazar)
    controller, constraint = _controller(bazar, hierarchy)
    target = pin.SE3(pin.rpy.rpyToMatrix(0, np.pi, 0), np.array([0.55, 0.3, 0.6]))
    task = controller.add_task("body_pose", "tool", TOOL, target=target, gain=5.0)
    task.enable()
    result = controller.compute(q)
    assert result.solved
    near = len(constraint.witnesses)
    assert near >= 1 and constraint.witnesses[0].distance < INFLUENCE
    problem = controller.problems[0]
    rows, lower = _pink_rows(bazar, q, near)
    qp = proxsuite.proxqp.dense.QP(len(problem.g), 0, len(lower), True)
    qp.settings.eps_abs, qp.settings.eps_rel = 1e-10, 0.0
    qp.init(problem.H, problem.g, None, None, rows, lower, np.full(len(lower), np.inf),
            problem.lower, problem.upper)
    qp.solve()
    assert qp.results.info.status == proxsuite.proxqp.QPSolverOutput.PROXQP_SOLVED
    first_level = controller.result.levels[0].command
    np.testing.assert_allclose(first_level, qp.results.x, atol=1e-6)
    assert np.max(rows @ first_level - lower) > -1e-9
    assert np.min(rows @ first_level - lower) < 1e-6, "the barrier is active"
