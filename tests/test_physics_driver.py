"""The MuJoCo driver's joint servo: a blocked joint neither winds up nor crushes, a
free body is measured, a weld holds a part and its release lets it fall."""

import mujoco
import numpy as np
import pytest

from conftest import write
from robocop_dsl.physics.driver import MujocoDriver
from robocop_dsl.physics.servo import Servo
from robocop_dsl.world import load_world

PERIOD = 0.01
STEP = 0.001


@pytest.fixture(scope="module")
def blocked(tmp_path_factory):
    """The pick world with a block fixed between the open fingers (a part held in a
    vice): closing the fingers blocks them at its faces, 2 cm from the middle."""
    pick = load_world("panda/panda_pick.yaml")
    tcp = [float(v) for v in pick.body_pose("panda_hand_tcp",
                                            pick.initial_configuration()).translation]
    folder = tmp_path_factory.mktemp("blocked")
    return load_world(write(folder, "blocked.yaml", f"""
        models:
          - include: panda/panda_pick.yaml
          - path: robocop/body.urdf
            namespace: block
            joint: {{position: {{linear: [{tcp[0]!r}, {tcp[1]!r}, {tcp[2]!r}]}}}}
    """))


def finger(driver):
    """The first finger's MuJoCo qpos, qvel and servo target addresses."""
    model = driver.model
    joint = model.joint("panda_finger_joint1")
    actuator = model.actuator("panda_finger_joint1_target").id
    return joint.qposadr[0], joint.dofadr[0], model.actuator_actadr[actuator]


def test_a_blocked_finger_neither_winds_up_nor_crushes(blocked):
    """Commanded to close for a second against the block, the finger stops at its face;
    the servo's target stays within the documented window of the finger (plus what the
    command and the finger moved in a period) and its force within
    min(effort, kv v_max) + (kp T + kv) |u|; commanded to open, it leaves as soon as its
    target has come back through the window (no wind-up from a second of squeezing)."""
    driver = MujocoDriver(blocked, "panda_all", PERIOD, STEP, Servo({}, {}))
    qpos, dof, act = finger(driver)
    kp, kv = driver.servo.gains("panda_finger_joint1")
    effort, v_max = 100.0, 0.2                      # the Panda URDF's finger limits
    speed = 0.1
    window = min(effort, kv * v_max) / kp
    assert window == pytest.approx(0.01)
    command = np.r_[np.zeros(7), -speed]
    forces = []
    for _ in range(100):
        before = driver.data.qpos[qpos]
        driver.write(command)
        driver.read()
        data = driver.data
        moved = abs(data.qpos[qpos] - before)
        assert abs(data.act[act] - data.qpos[qpos]) <= window + speed * PERIOD + moved + 1e-9
        force = abs(data.qfrc_actuator[dof])
        assert force <= effort + 1e-9
        if abs(data.qvel[dof]) < 1e-3:
            forces.append(force)
    assert driver.data.qpos[qpos] == pytest.approx(0.02, abs=1.5e-3)
    assert len(forces) > 50
    assert max(forces) <= min(effort, kv * v_max) + (kp * PERIOD + kv) * speed + 1e-6
    assert max(forces[-10:]) > 0.5 * min(effort, kv * v_max)   # it does squeeze
    closed = driver.data.qpos[qpos]
    driver.write(-command)
    for _ in range(round((window + 0.005) / speed / PERIOD)):   # the window, then 5 mm
        driver.read()
    assert driver.data.qpos[qpos] > closed + 0.003


def test_free_bodies_come_from_the_physics():
    """The cube on the table is measured: pinocchio's configuration puts it where
    MuJoCo has it, at rest on the table, and its velocity is zero."""
    world = load_world("panda/panda_pick.yaml")
    driver = MujocoDriver(world, "panda_all", PERIOD, STEP)
    for _ in range(50):
        q, v = driver.read()
    pose = world.body_pose("cube_body", q)
    assert np.allclose(pose.homogeneous, driver.body_pose("cube_body").homogeneous,
                       atol=1e-12)
    assert pose.translation[2] == pytest.approx(0.77, abs=5e-4)
    joint = world.model.joints[world.model.frames[world.body_frame_id("cube_body")].parentJoint]
    assert np.abs(v[joint.idx_v:joint.idx_v + 6]).max() < 1e-3


def test_a_weld_carries_the_cube_and_its_release_drops_it(blocked):
    """Welded to the hand between the fingers, the cube rises with the hand; released,
    it falls onto the table."""
    world = load_world("panda/panda_pick.yaml")
    q = world.initial_configuration()
    tcp = world.body_pose("panda_hand_tcp", q)
    free = world.model.frames[world.body_frame_id("cube_body")].parentJoint
    start = world.model.joints[free].idx_q
    placement = world.model.jointPlacements[free]
    import pinocchio as pin

    q[start:start + 7] = pin.SE3ToXYZQUAT(placement.actInv(tcp))
    driver = MujocoDriver(world, "panda_all", PERIOD, STEP, initial=q)
    driver.attach("cube_body", "panda_hand")
    lift = np.r_[0, -0.3, 0, 0, 0, 0, 0, 0]          # joint 2 back: the hand rises
    held = []
    for _ in range(50):
        driver.write(lift)
        q, _ = driver.read()
        held.append(world.body_pose("panda_hand", q).actInv(
            world.body_pose("cube_body", q)).translation)
    assert np.ptp(np.array(held), axis=0).max() < 2e-3
    driver.hold()
    driver.detach("cube_body")
    for _ in range(100):
        q, _ = driver.read()
    assert world.body_pose("cube_body", q).translation[2] == pytest.approx(0.77, abs=2e-3)


def test_attaching_a_fixed_body_is_refused():
    driver = MujocoDriver(load_world("panda/panda_pick.yaml"), "panda_all", PERIOD, STEP)
    with pytest.raises(ValueError, match="'target_point' in physics: it is not a free body"):
        driver.attach("target_point", "panda_hand")


def test_mass_and_friction_of_a_sample():
    world = load_world("panda/panda_pick.yaml")
    driver = MujocoDriver(world, "panda_all", PERIOD, STEP,
                          physics={"friction": 0.3, "mass": {"cube_body": 0.4}})
    cube = driver.model.body("cube_body")
    assert cube.mass[0] == pytest.approx(0.4)
    assert np.allclose(cube.inertia, 4 * 2.667e-5)
    assert np.allclose(driver.model.geom_friction[:, 0], 0.3)
    assert driver.model.body_subtreemass[0] == pytest.approx(
        mujoco.MjModel.from_xml_string(driver.physics.spec.to_xml()).body_subtreemass[0] + 0.3)
