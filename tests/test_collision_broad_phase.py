"""The pairs a collision scene follows from cycle to cycle are exactly those a full
search finds: along random motions, with continuous and mimic joints, and across an
attachment; the reach of every shape bounds how far it moves."""

import numpy as np
import pinocchio as pin
import pytest

from robocop_dsl.control.kinematics import Kinematics
from robocop_dsl.world import load_world
from robocop_dsl.world.collision_scene import CollisionScene
from robocop_dsl.world.collisions import checked_pairs, reach

WITHIN = 0.08


def _full_search(world, pairs, q) -> dict:
    """Distance of every shape pair closer than WITHIN, by a fresh scene's boxes and coal."""
    scene = CollisionScene(world, pairs)
    kinematics = Kinematics(world)
    kinematics.update(q)
    scene.place(kinematics)
    return {(w.first.name, w.second.name): w.distance for w in scene.closest(WITHIN)}


def _random_walk(world, group, rng, steps):
    """Configurations along a random walk of ``group``: mostly small steps, some jumps."""
    model = world.model
    q = world.initial_configuration()
    joints = world.joint_group(group)
    for _ in range(steps):
        velocity = np.zeros(model.nv)
        scale = 0.6 if rng.uniform() < 0.1 else 0.03
        velocity[joints.v_indices] = rng.normal(0.0, scale, joints.dofs)
        q = pin.integrate(model, q, velocity)
        q = np.clip(q, model.lowerPositionLimit, model.upperPositionLimit)
        yield q


@pytest.mark.parametrize("path, group, first, second", [
    ("bazar/sophia.yaml", "bazar_arms", "bazar_arms", "bazar_arms"),
    ("bazar/sophia.yaml", "bazar_arms", "bazar_arms", "workbench"),
    ("kinova/jaco.yaml", "jaco_arm", "jaco_arm", "jaco_arm"),
    ("panda/panda_on_table.yaml", "panda_arm", "panda_arm", "table"),
])
def test_followed_pairs_are_those_a_full_search_finds(path, group, first, second):
    world = load_world(path)
    pairs = checked_pairs(world, first, second)
    scene = CollisionScene(world, pairs)
    kinematics = Kinematics(world)
    rng = np.random.default_rng(11)
    seen = 0
    for q in _random_walk(world, group, rng, 300):
        kinematics.update(q)
        followed = {(w.first.name, w.second.name): w.distance
                    for w in scene.near(kinematics, WITHIN)}
        expected = _full_search(world, pairs, q)
        assert followed.keys() == expected.keys()
        for key, distance in expected.items():
            assert followed[key] == pytest.approx(distance, abs=1e-5)
        seen += len(expected)
    assert seen > 0


def test_panda_fingers_moving_are_followed(panda):
    pairs = checked_pairs(panda, "panda_hand", "table") + checked_pairs(
        panda, "panda_leftfinger", "table") + checked_pairs(panda, "panda_rightfinger", "table")
    scene = CollisionScene(panda, pairs)
    kinematics = Kinematics(panda)
    finger = panda.model.joints[panda.model.getJointId("panda_finger_joint1")].idx_q
    q = panda.initial_configuration()
    q[panda.joint_group("panda_arm").q_indices] = [0, 0.9, 0, -1.2, 0, 2.1, 0.8]
    seen = 0
    for opening in np.linspace(0.0, 0.04, 41):
        q[finger] = opening
        q[panda.joint_group("panda_arm").q_indices[1]] += 0.01
        kinematics.update(q)
        followed = {(w.first.name, w.second.name) for w in scene.near(kinematics, 0.3)}
        expected = set(_closest_within(panda, pairs, q, 0.3))
        assert followed == expected
        seen += len(expected)
    assert seen > 0


def _closest_within(world, pairs, q, within):
    scene = CollisionScene(world, pairs)
    kinematics = Kinematics(world)
    kinematics.update(q)
    scene.place(kinematics)
    return [(w.first.name, w.second.name) for w in scene.closest(within)]


def test_an_attached_body_is_followed_with_its_new_carrier(bazar):
    world = bazar.copy()
    pairs = checked_pairs(world, "part_body", "bazar_left_arm")
    scene = CollisionScene(world, pairs)
    kinematics = Kinematics(world)
    q = world.initial_configuration()
    kinematics.update(q)
    assert scene.near(kinematics, 0.2) == []
    tool = "bazar_right_hankamp_tool_object_side"
    kinematics.place("part_body", tool, pin.SE3(np.eye(3), np.array([0, 0, 0.08])))
    arm = world.joint_group("bazar_right_arm")
    distances = []
    for shoulder in np.linspace(0.0, 1.2, 60):
        q[arm.q_indices[0]] = shoulder
        kinematics.update(q)
        followed = {(w.first.name, w.second.name): w.distance
                    for w in scene.near(kinematics, 0.2)}
        placed = CollisionScene(world, pairs)
        placed.place(kinematics)
        expected = {(w.first.name, w.second.name): w.distance for w in placed.closest(0.2)}
        assert followed.keys() == expected.keys()
        for key, distance in expected.items():
            assert followed[key] == pytest.approx(distance, abs=1e-5)
        distances.append(min(expected.values(), default=np.inf))
    assert min(distances) < 0.2 < distances[0]


@pytest.mark.parametrize("path, group", [("bazar/sophia.yaml", "bazar_arms"),
                                         ("kinova/jaco.yaml", "jaco_arm"),
                                         ("panda/panda_on_table.yaml", "panda_arm")])
def test_reach_bounds_how_far_every_shape_moves(path, group):
    """Between random configurations, every corner of every shape's box moves at most
    the shape's reach times the coordinates' change."""
    world = load_world(path)
    pairs = checked_pairs(world, group, group)
    scene = CollisionScene(world, pairs)
    table = reach(world.model, scene._frame_of, scene._centers, scene._half)
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
    rng = np.random.default_rng(5)
    model = world.model
    joints = world.joint_group(group)
    tightest = 0.0
    for _ in range(200):
        velocity = np.zeros(model.nv)
        velocity[joints.v_indices] = rng.normal(0.0, 1.0, joints.dofs)
        q1 = pin.integrate(model, world.initial_configuration(), velocity)
        velocity[joints.v_indices] = rng.normal(0.0, 0.3, joints.dofs)
        q2 = pin.integrate(model, q1, velocity)
        bound = table @ np.abs(q2 - q1)
        for index, frame in enumerate(scene._frame_of):
            points = scene._centers[index] + corners * scene._half[index]
            travel = np.linalg.norm(_placed(world, q2, frame, points)
                                    - _placed(world, q1, frame, points), axis=1).max()
            assert travel <= bound[index] + 1e-12
            if bound[index] > 0:
                tightest = max(tightest, travel / bound[index])
    assert tightest > 0.2


def _placed(world, q, frame, points):
    data = world.model.createData()
    pin.framesForwardKinematics(world.model, data, q)
    pose = data.oMf[frame]
    return points @ pose.rotation.T + pose.translation
