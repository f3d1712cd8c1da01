"""The collision_avoidance constraint on the real BAZAR: rows only for the pairs near,
rows that are the distance's derivative, the damper's bound, parameter checks."""

import numpy as np
import pinocchio as pin
import pytest

from robocop_dsl.control import Controller
from robocop_dsl.control.constraints.velocity_damper import damper_bounds
from robocop_dsl.control.exceptions import InvalidParameter, UnknownName
from robocop_dsl.control.kinematics import Kinematics
from robocop_dsl.world import load_world
from robocop_dsl.world.collision_scene import CollisionScene

GROUP = "bazar_upper_joints"


def _constraint(world, first="bazar_arms", other="workbench", **parameters):
    controller = Controller(world, GROUP, 0.005)
    return controller, controller.add_constraint("collision_avoidance", "clear", first,
                                                 other=other, **parameters)


def _bent(world):
    """The left arm folded so that its tool comes close to its own upper arm."""
    q = world.initial_configuration()
    q[world.joint_group("bazar_left_arm").q_indices] = [0, 0.6, 0, -2.0, 0, -1.6, 0]
    return q


def test_nothing_near_costs_no_row(bazar):
    controller, constraint = _constraint(bazar)
    controller.update_state(bazar.initial_configuration())
    assert constraint.rows == 0 and constraint.witnesses == []
    assert constraint.pairs_checked == 14


def test_rows_are_the_derivative_of_the_distance(bazar):
    controller, constraint = _constraint(bazar, "bazar_left_arm", "bazar_left_arm",
                                         min_distance=0.01, influence=0.15)
    q = _bent(bazar)
    controller.update_state(q)
    assert constraint.rows >= len(constraint.witnesses) >= 1
    jacobian = constraint.compute_jacobian(controller.state)
    lower, upper = constraint.compute_bounds(controller.state)
    assert np.all(np.isinf(upper))
    scene = CollisionScene(bazar, [(w.first.body, w.second.body) for w in constraint.witnesses])
    kinematics = Kinematics(bazar)
    group = controller.state.group
    rng = np.random.default_rng(1)
    for row, witness in enumerate(constraint.witnesses):
        index = next(i for i in range(scene.size)
                     if (scene.shapes[scene.first[i]].name, scene.shapes[scene.second[i]].name)
                     == (witness.first.name, witness.second.name))
        velocity = rng.normal(size=group.dofs)
        step = 1e-3     # coal's GJK gives curved shapes' distances to about 1e-7 m

        def distance(sign):
            moved = q.copy()
            moved[group.q_indices] += sign * step * velocity
            kinematics.update(moved)
            scene.place(kinematics)
            return scene.witness(index).distance

        rate = (distance(1) - distance(-1)) / (2 * step)
        assert jacobian[row] @ velocity == pytest.approx(rate, rel=0.01, abs=1e-3)
        assert lower[row] == pytest.approx(-5.0 * (witness.distance - 0.01))
    assert np.all(np.isneginf(lower[len(constraint.witnesses):]))
    assert not np.any(jacobian[len(constraint.witnesses):])


def test_a_pair_closing_faster_than_the_damper_brakes_to_a_stop():
    """Closing faster than the damper allows, a pair is asked to brake to a stop; closer
    than the smallest distance, it is pushed apart to remove the overlap in 50 ms (up to
    2 cm/s, or at the damper's rate if faster)."""
    gap, dt = 0.03, 0.005
    assert damper_bounds(-4.0 * gap, -0.05, 4.0, dt) == pytest.approx(-4.0 * gap)
    fast = -0.3
    stop = fast + dt * fast ** 2 / (2 * gap)
    assert damper_bounds(-4.0 * gap, fast, 4.0, dt) == pytest.approx(stop)
    assert damper_bounds(4.0 * 0.0005, fast, 4.0, dt) == pytest.approx(0.0005 / 0.05)
    assert damper_bounds(4.0 * 0.002, fast, 4.0, dt) == pytest.approx(0.02)
    assert damper_bounds(40.0 * 0.002, fast, 40.0, dt) == pytest.approx(40.0 * 0.002)
    bounds = damper_bounds(np.array([-4.0 * gap, -2.0 * gap]), np.array([-0.05, fast]),
                           np.array([4.0, 2.0]), dt)
    assert bounds == pytest.approx([-4.0 * gap, stop])


def test_parameters_are_checked(bazar):
    controller, constraint = _constraint(bazar, min_distance=0.15, influence=0.3)
    assert (constraint.min_distance, constraint.influence) == (0.15, 0.3)
    with pytest.raises(InvalidParameter, match="below influence"):
        constraint.min_distance = 0.4
    with pytest.raises(InvalidParameter, match="1 / time step"):
        constraint.damping = 300.0
    with pytest.raises(UnknownName, match="did you mean 'bazar_arms'"):
        controller.add_constraint("collision_avoidance", "other", "bazar_armz")
    constraint.configure(damping=2.0, influence=0.2)
    assert constraint.parameters() == {"other": "workbench", "min_distance": 0.15,
                                       "influence": 0.2, "damping": 2.0}


def test_an_attached_body_carries_its_shapes(bazar):
    world = bazar.copy()
    controller = Controller(world, GROUP, 0.005)
    constraint = controller.add_constraint("collision_avoidance", "part", "part_body",
                                           other="bazar_right_arm", influence=0.2)
    q = world.initial_configuration()
    controller.update_state(q)
    scene = constraint.watch.scene
    scene.place(controller.kinematics)
    assert scene.clearance() > 0.3
    tool = "bazar_right_hankamp_tool_object_side"
    # the 4 cm cube centred 8 cm beyond the tip of the tool's 14 cm long box
    controller.kinematics.place("part_body", tool, pin.SE3(np.eye(3), np.array([0, 0, 0.08])))
    controller.kinematics.update(q)
    scene.place(controller.kinematics)
    assert scene.clearance() == pytest.approx(0.06, abs=1e-6)


@pytest.mark.parametrize("path", ["bazar/sophia.yaml", "panda/panda_on_table.yaml"])
def test_joint_columns_give_every_joint_jacobian(path):
    world = load_world(path)
    kinematics = Kinematics(world)
    model = world.model
    q = pin.randomConfiguration(model, np.maximum(model.lowerPositionLimit, -3.0),
                                np.minimum(model.upperPositionLimit, 3.0))
    kinematics.update(q)
    for joint in range(1, model.njoints):
        expected = pin.getJointJacobian(model, kinematics.data, joint, pin.WORLD)
        found = (kinematics.joint_columns * kinematics.supports[joint]) @ kinematics.fold
        np.testing.assert_allclose(found, expected, atol=1e-12)


def test_rows_follow_a_mimic_joint():
    """The Panda's right finger slides with the left one's coordinate (a mimic joint):
    its pairs with the table have rows in the gripper's column, the distances' rates (the
    hand turned so that the fingers open up and down)."""
    panda = load_world("panda/panda_on_table.yaml")
    controller = Controller(panda, "panda_gripper", 0.002)
    constraint = controller.add_constraint("collision_avoidance", "clear", "panda_gripper",
                                           other="table", influence=3.0)
    q = panda.initial_configuration()
    q[panda.joint_group("panda_arm").q_indices] = [0, -0.785, 0, -2.356, 0.8, 1.571, 0.785]
    q[panda.joint_group("panda_gripper").q_indices] = 0.02
    controller.update_state(q)
    assert constraint.rows >= len(constraint.witnesses)
    jacobian = constraint.compute_jacobian(controller.state)
    witnesses = constraint.witnesses
    assert {w.second.body for w in witnesses} == {"panda_leftfinger", "panda_rightfinger"}
    scene = CollisionScene(panda, [("table", "panda_leftfinger"), ("table", "panda_rightfinger")])
    kinematics = Kinematics(panda)
    step = 1e-3     # coal's GJK gives distances to about 1e-6 m
    for row, witness in enumerate(witnesses):
        index = next(i for i in range(scene.size)
                     if (scene.shapes[scene.first[i]].name, scene.shapes[scene.second[i]].name)
                     == (witness.first.name, witness.second.name))

        def distance(sign, index=index):
            moved = q.copy()
            moved[panda.joint_group("panda_gripper").q_indices] += sign * step
            kinematics.update(moved)
            scene.place(kinematics)
            return scene.witness(index).distance

        rate = (distance(1) - distance(-1)) / (2 * step)
        assert jacobian[row, 0] == pytest.approx(rate, rel=0.01, abs=1e-3)
    rates = {w.second.body: np.sign(jacobian[row, 0]) for row, w in enumerate(witnesses)}
    assert rates == {"panda_leftfinger": -1.0, "panda_rightfinger": 1.0}


def test_rows_written_into_the_qp_are_the_constraints_own(bazar):
    """The rows the constraint writes straight into the QP are those of its hooks, as
    pairs come and go: 6 pairs, 5 (same QP, a stale row cleared), 3 (the QP keeps its
    rows for this cycle), none (the QP has shrunk to none), 6 (the QP grows at the next
    cycle), 6, 3, 3 (the QP shrinks to 4 rows), 6 (its 4 rows go to the 4 closest
    pairs); the velocity limit's rows stay as they are."""
    over = np.array([-0.15, 1.2, 0, -2.0, 0, -1.6, 0, 0.15, 1.2, 0, -1.4, 0, 1.0, 0])
    controller = Controller(bazar, GROUP, 0.005)
    speed = controller.add_constraint("body_velocity", "speed",
                                      "bazar_left_hankamp_tool_object_side", max_linear=0.5)
    clear = controller.add_constraint("collision_avoidance", "clear", "bazar_arms",
                                      other="workbench", influence=0.25)
    arms = bazar.joint_group("bazar_arms").q_indices
    counts = []
    for share in (1.0, 0.95, 0.9, 0.0, 1.0, 1.0, 0.9, 0.9, 1.0):
        q = bazar.initial_configuration()
        q[arms] = share * over + (1 - share) * q[arms]
        assert controller.compute(q).solved
        problem = controller.problems[0]
        counts.append((clear.pairs_near, len(problem.C) - speed.rows))
        state = controller.state
        jacobian = np.vstack([speed.compute_jacobian(state), clear.compute_jacobian(state)])
        lower = np.concatenate([speed.compute_bounds(state)[0], clear.compute_bounds(state)[0]])
        upper = np.concatenate([speed.compute_bounds(state)[1], clear.compute_bounds(state)[1]])
        np.testing.assert_array_equal(problem.C, jacobian)
        np.testing.assert_array_equal(problem.l, lower)
        np.testing.assert_array_equal(problem.u, upper)
        unused = speed.rows + clear.pairs_near
        assert not problem.C[unused:].any() and np.all(np.isneginf(problem.l[unused:]))
        rows = len(problem.C) - speed.rows
        distances = sorted(w.distance for w in clear.witnesses)[:rows]
        np.testing.assert_allclose(sorted(problem.l[speed.rows:speed.rows + len(distances)]),
                                   sorted(-5.0 * (np.array(distances) - 0.01)), atol=1e-12)
    assert counts == [(6, 8), (5, 8), (3, 8), (0, 0), (6, 0), (6, 8), (3, 8), (3, 4), (6, 4)]
