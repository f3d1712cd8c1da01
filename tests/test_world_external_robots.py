"""Robots nobody here wrote: URDFs from the example-robot-data package."""

import textwrap

import numpy as np

from robocop_dsl.world import load_world

ROBOTS = "example-robot-data/robots"


def world_of(tmp_path, body):
    path = tmp_path / "w.yaml"
    path.write_text(textwrap.dedent(body).lstrip("\n"))
    return load_world(path)


def test_panda_on_a_table(panda):
    """Meshes through package://, a mimic finger joint, a virtual target point."""
    assert panda.joint_group("panda_arm").dofs == 7
    assert panda.joint("panda_finger_joint2").type == "mimic"
    assert panda.joint("panda_finger_joint2").mimic == "panda_finger_joint1"
    assert panda.body("panda_link0").parent == "table"
    assert len(panda.visual_model.geometryObjects) > 10
    meshes = [g.meshPath for g in panda.visual_model.geometryObjects if "/" in g.meshPath]
    assert meshes and all(m.startswith("/") and m.endswith(".dae") for m in meshes)
    q = panda.initial_configuration()
    np.testing.assert_allclose(panda.body_pose("target_point", q).translation, [0.45, 0.2, 1.05])
    np.testing.assert_allclose(panda.body_pose("panda_link0", q).translation, [0, 0, 0.75])


def test_baxter_with_continuous_and_mimic_joints(tmp_path):
    world = world_of(tmp_path, f"""
        models:
          - path: {ROBOTS}/baxter_description/urdf/baxter.urdf
            namespace: baxter
    """)
    types = {world.joint(j).type for j in world.joint_names()}
    assert {"revolute", "mimic", "fixed"} <= types
    assert world.has_body("baxter_left_gripper")
    assert world.model.nq > 14
    assert len(world.visual_model.geometryObjects) > 20


def test_talos_with_a_floating_base(tmp_path):
    world = world_of(tmp_path, f"""
        models:
          - path: {ROBOTS}/talos_data/robots/talos_reduced.urdf
            joint: {{type: floating}}
    """)
    base = world.joint("world_to_base_link")
    assert (base.type, base.dofs) == ("floating", 6)
    assert world.model.nq == world.model.nv + 1
    assert world.has_body("gripper_left_base_link")


def test_ur5_with_continuous_joints(tmp_path):
    world = world_of(tmp_path, f"""
        models:
          - path: {ROBOTS}/ur_description/urdf/ur5_robot.urdf
            namespace: ur5
        joint_groups:
          arm: [ur5_shoulder_pan_joint, ur5_shoulder_lift_joint, ur5_elbow_joint,
                ur5_wrist_1_joint, ur5_wrist_2_joint, ur5_wrist_3_joint]
    """)
    assert world.joint_group("arm").dofs == 6
