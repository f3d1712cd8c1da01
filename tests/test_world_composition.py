"""Namespaces through nested includes, path resolution order, groups and processors."""

import numpy as np

from robocop_dsl.world import load_world

from conftest import write


def test_namespaces_nest_through_includes(tmp_path):
    """outer includes middle with namespace 'outer', middle includes inner with 'mid'."""
    write(tmp_path, "inner.yaml", """
        models:
          - path: robocop/point.urdf
            namespace: tip
            joint:
              name: hinge
              type: revolute
              limits: {lower: -1, upper: 1, velocity: 1}
        joint_groups:
          door: [hinge]
    """)
    write(tmp_path, "middle.yaml", """
        models:
          - include: inner.yaml
            namespace: mid
          - path: robocop/body.urdf
            joint: {parent: mid_tip_point}
    """)
    path = write(tmp_path, "outer.yaml", """
        models:
          - include: middle.yaml
            namespace: outer
    """)
    world = load_world(path)
    assert world.has_body("outer_mid_tip_point")
    assert world.body("outer_body").parent == "outer_mid_tip_point"
    assert world.body("outer_mid_tip_point").joint == "outer_mid_hinge"
    assert world.body("outer_body").joint == "outer_mid_tip_point_to_outer_body"
    assert world.group_names() == ["outer_mid_door"]
    assert world.joint_group("outer_mid_door").joints == ("outer_mid_hinge",)


def test_bazar_names(bazar):
    for body in ("bazar_left_hankamp_tool_object_side", "bazar_right_hankamp_tool_object_side",
                 "pickup_point", "drop_point", "part_body", "workbench",
                 "bazar_left_tool_adapter_tool_side", "bazar_ptu_mount_link"):
        assert bazar.has_body(body), body
    assert bazar.body("kinect2_link").parent == "bazar_ptu_mount_link"
    dofs = {g: bazar.joint_group(g).dofs for g in bazar.group_names()}
    assert dofs == {"bazar_left_arm": 7, "bazar_right_arm": 7, "bazar_arms": 14,
                    "bazar_ptu": 2, "bazar_upper_joints": 16}
    assert bazar.controller_names() == ["whole_body_controller"]
    options = bazar.processors["whole_body_controller"].options
    assert options == {"joint_group": "bazar_upper_joints", "time_step": 0.005,
                       "solver": "auto", "hierarchy": "strict"}


def test_bazar_limits_from_the_datasheet(bazar):
    arm = bazar.joint_group("bazar_left_arm")
    np.testing.assert_allclose(np.degrees(arm.upper), [170, 120, 170, 120, 170, 120, 170])
    np.testing.assert_allclose(np.degrees(arm.lower), -np.degrees(arm.upper))
    np.testing.assert_allclose(np.degrees(arm.max_velocity), [110, 110, 128, 128, 204, 184, 184],
                               atol=1e-4)


def test_initial_posture_applies_to_the_group(bazar):
    q = bazar.initial_configuration()
    arms = bazar.joint_group("bazar_arms")
    np.testing.assert_allclose(q[arms.q_indices], [0, 0, 0, -0.5, 0, 0.5, 0] * 2)


def test_search_order_own_folder_first(tmp_path, monkeypatch):
    """The including file's folder wins over robots/, which wins over ROBOCOP_PATH."""
    write(tmp_path / "local", "robocop/point.urdf", '<robot name="p"><link name="mine"/></robot>')
    extra = tmp_path / "extra"
    write(extra, "robocop/point.urdf", '<robot name="p"><link name="theirs"/></robot>')
    write(extra, "only_here.urdf", '<robot name="o"><link name="found_on_path"/></robot>')
    monkeypatch.setenv("ROBOCOP_PATH", str(extra))
    local = write(tmp_path / "local", "w.yaml", """
        models:
          - path: robocop/point.urdf
          - path: only_here.urdf
    """)
    assert {"mine", "found_on_path"} <= set(load_world(local).body_names())
    elsewhere = write(tmp_path / "other", "w.yaml", """
        models:
          - path: robocop/point.urdf
    """)
    assert "point" in load_world(elsewhere).body_names()


def test_world_joint_between_models(tmp_path):
    """A model joint may be revolute with an axis, limits and a name."""
    path = write(tmp_path, "w.yaml", """
        models:
          - path: robocop/body.urdf
            namespace: door
            joint:
              type: revolute
              name: hinge
              axis: [0, 0, 1]
              position: {linear: [1, 0, 0]}
              limits: {lower: -1.5, upper: 1.5, velocity: 2}
    """)
    world = load_world(path)
    hinge = world.joint("hinge")
    assert (hinge.type, hinge.parent, hinge.child, hinge.dofs) == ("revolute", "world", "door_body", 1)
    q = np.array([np.pi / 2])
    np.testing.assert_allclose(world.body_pose("door_body", q).translation, [1, 0, 0])
    np.testing.assert_allclose(world.body_pose("door_body", q).rotation[:, 0], [0, 1, 0],
                               atol=1e-12)
