"""Collision geometry of worlds: bodies, sets, pairs left out (adjacent, SRDF,
``allowed_collisions:``, rigidly joined), distances, and ``world`` listing them."""

import json
import subprocess
import sys

import numpy as np
import pytest

from conftest import write
from robocop_dsl.cli.main import main
from robocop_dsl.control.kinematics import Kinematics
from robocop_dsl.diagnostics import DiagnosticError
from robocop_dsl.world import load_world
from robocop_dsl.world.collision_scene import CollisionScene
from robocop_dsl.world.collisions import checked_pairs, collision_geometry, set_bodies


def test_a_joint_group_stands_for_the_bodies_its_joints_move(bazar):
    assert set_bodies(bazar, "bazar_left_arm") == (
        "bazar_left_link_1", "bazar_left_link_2", "bazar_left_link_3", "bazar_left_link_4",
        "bazar_left_link_5", "bazar_left_link_6", "bazar_left_hankamp_tool_robot_side")
    assert set_bodies(bazar, "workbench") == ("workbench",)
    assert set_bodies(bazar, "pickup_point") == ()
    with pytest.raises(KeyError):
        set_bodies(bazar, "bazar_arm")


def test_adjacent_and_rigidly_joined_pairs_are_left_out(bazar):
    own = checked_pairs(bazar, "bazar_left_arm", "bazar_left_arm")
    assert ("bazar_left_link_1", "bazar_left_link_2") not in own
    # link_7 has no geometry: the tool on its flange is adjacent to link_6
    assert ("bazar_left_link_6", "bazar_left_hankamp_tool_robot_side") not in own
    assert ("bazar_left_link_5", "bazar_left_hankamp_tool_robot_side") in own
    assert len(own) == 15
    assert len(checked_pairs(bazar, "bazar_left_arm", "bazar_right_arm")) == 49
    # the workbench and the robot's base never move apart
    assert checked_pairs(bazar, "workbench", "bazar_root_body") == []


def test_srdf_disabled_pairs_are_left_out(panda):
    pairs = checked_pairs(panda, "panda_arm", "panda_arm")
    assert ("panda_link1", "panda_link3") not in pairs          # SRDF: Never
    assert ("panda_leftfinger", "panda_rightfinger") not in pairs  # SRDF: Default
    assert ("panda_link1", "panda_link5") in pairs
    assert ("panda_link5", "panda_leftfinger") in pairs
    assert frozenset(("panda_link3", "panda_link5")) in panda.allowed_collisions


def test_meshes_become_convex_hulls_and_distances_match_coal(panda):
    import coal

    geometry = collision_geometry(panda)
    [hand] = geometry.by_body["panda_hand"]
    assert isinstance(hand.geometry, coal.ConvexBase)
    scene = CollisionScene(panda, checked_pairs(panda, "panda_arm", "table"))
    kinematics = Kinematics(panda)
    kinematics.update(panda.initial_configuration())
    scene.place(kinematics)
    lower = scene.box_distances()
    witnesses = [scene.witness(i) for i in range(scene.size)]
    assert all(bound <= w.distance + 1e-9 for bound, w in zip(lower, witnesses))
    closest = min(witnesses, key=lambda w: w.distance)
    assert scene.clearance() == pytest.approx(closest.distance)
    gap = closest.point_second - closest.point_first
    assert np.linalg.norm(gap) == pytest.approx(closest.distance, abs=1e-9)
    assert np.linalg.norm(closest.normal) == pytest.approx(1.0)


def test_allowed_collisions_and_srdf_in_a_world_file(tmp_path):
    write(tmp_path, "cell.yaml", """
        models:
          - include: bazar/fixed_bazar.yaml
            namespace: bazar
          - path: bazar/models/workbench.urdf
            joint: {position: {linear: [0.7, 0, 0.5]}}
        allowed_collisions:
          - [bazar_left_link_6, bazar_left_link_4]
        """)
    world = load_world(tmp_path / "cell.yaml")
    pairs = checked_pairs(world, "bazar_left_arm", "bazar_left_arm")
    assert ("bazar_left_link_4", "bazar_left_link_6") not in pairs
    assert ("bazar_left_link_3", "bazar_left_link_6") in pairs


def test_bad_collision_entries_are_located(tmp_path):
    write(tmp_path, "bad.yaml", """
        models:
          - path: bazar/models/workbench.urdf
            srdf: nowhere/workbench.srdf
        allowed_collisions:
          - [workbench, wrkbench]
          - workbench
        """)
    write(tmp_path, "arm.srdf", """
        <robot name="lwr4">
          <disable_collisions link1="link_1" link2="link_9" reason="Never"/>
        </robot>
        """)
    write(tmp_path, "arm.yaml", """
        models:
          - path: bazar/models/lwr4.urdf
            srdf: arm.srdf
        """)
    with pytest.raises(DiagnosticError) as caught:
        load_world(tmp_path / "bad.yaml")
    found = [(d.code, d.span.line, d.message) for d in caught.value.diagnostics]
    assert found == [
        ("urdf-not-found", 3, "cannot find SRDF 'nowhere/workbench.srdf'"),
        ("invalid-entry", 6, "an allowed collision is a pair of body names"),
        ("unknown-body", 5, "allowed collision names unknown body 'wrkbench'")]
    with pytest.raises(DiagnosticError) as caught:
        load_world(tmp_path / "arm.yaml")
    [problem] = caught.value.diagnostics
    assert (problem.code, problem.span.line) == ("unknown-body", 2)
    assert "link_9" in problem.message and problem.file.endswith("arm.srdf")


def test_world_lists_collision_bodies_and_checked_pairs(capsys):
    assert main(["world", "panda/panda_on_table.yaml"]) == 0
    out = capsys.readouterr().out
    assert "collision bodies (12):" in out
    assert "  panda_hand: convex hull of 102 points" in out
    assert "checked pairs (30; adjacent bodies, bodies that no joint moves apart and 35 " \
           "allowed pairs left out):" in out
    assert "  table: panda_link1, panda_link2," in out


def test_world_json_has_the_collision_pairs():
    done = subprocess.run([sys.executable, "-m", "robocop_dsl", "world", "bazar/sophia.yaml",
                           "--format", "json"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    found = json.loads(done.stdout)["collisions"]
    assert {"name": "workbench", "shapes": ["box 0.6 x 1.2 x 0.04 m"]} in found["bodies"]
    assert ["bazar_left_link_1", "workbench"] in found["checked_pairs"]
    assert ["bazar_left_link_1", "bazar_left_link_2"] not in found["checked_pairs"]
