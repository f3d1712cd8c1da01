"""Models whose URDF has its own ``world`` root link are placed by their ``joint:``."""

import json

import numpy as np
import pinocchio as pin
import pytest

from robocop_dsl.cli.main import main
from robocop_dsl.diagnostics import DiagnosticError
from robocop_dsl.world import load_world, resolve_world_path

from conftest import write

UR5 = "example-robot-data/robots/ur_description/urdf/ur5_robot.urdf"
TWO_DOFS = "example-robot-data/robots/asr_twodof_description/urdf/TwoDofs.urdf"
TABLE = [0.5, 0.2, 0.8]
UR5_ON_TABLE = f"""
    models:
      - path: robocop/body.urdf
        namespace: table
        joint:
          position: {{linear: {TABLE}}}
      - path: {UR5}
        namespace: ur5
        joint:
          parent: table_body
"""


def direct_model(name):
    """The URDF ``name`` (along the robots path) loaded by pinocchio as it is."""
    return pin.buildModelFromUrdf(str(resolve_world_path(name)))


def same_motion(world, model, prefix, seed=3):
    """Configurations of ``world`` and ``model`` after one shared random velocity."""
    v = np.random.default_rng(seed).uniform(-1, 1, model.nv)
    v_world = np.zeros(world.model.nv)
    for joint_id in range(1, model.njoints):
        source = model.joints[joint_id]
        target = world.model.joints[world.model.getJointId(prefix + model.names[joint_id])]
        v_world[target.idx_v:target.idx_v + target.nv] = v[source.idx_v:source.idx_v + source.nv]
    return (pin.integrate(world.model, world.neutral_configuration(), v_world),
            pin.integrate(model, pin.neutral(model), v))


def pose_in(model, q, frame):
    """World pose of ``frame`` of ``model`` at ``q`` (``pin.SE3``)."""
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    return data.oMf[model.getFrameId(frame, pin.FrameType.BODY)]


def test_ur5_on_a_table_sits_where_its_joint_says(tmp_path):
    world = load_world(write(tmp_path, "w.yaml", UR5_ON_TABLE))
    assert world.body("ur5_base_link").parent == "table_body"
    assert not world.has_body("ur5_world")
    model = direct_model(UR5)
    q_world, q = same_motion(world, model, "ur5_")
    table = pin.SE3(np.eye(3), np.array(TABLE))
    for body in ("base_link", "wrist_3_link", "tool0"):
        expected = table * pose_in(model, q, body)
        got = world.body_pose(f"ur5_{body}", q_world)
        np.testing.assert_allclose(got.homogeneous, expected.homogeneous, atol=1e-9)
    np.testing.assert_allclose(
        world.body_pose("ur5_base_link", q_world).translation, TABLE, atol=1e-12)


def test_own_world_joint_is_composed_after_the_model_joint(tmp_path):
    """TwoDofs turns its base by -1.57 rad about z under its own world link."""
    world = load_world(write(tmp_path, "w.yaml", f"""
        models:
          - path: {TWO_DOFS}
            namespace: arm
            joint:
              position: {{linear: [1, 2, 3], angular: [0.3, 0, 0.5]}}
    """))
    model = direct_model(TWO_DOFS)
    q_world, q = same_motion(world, model, "arm_")
    placement = pin.SE3(pin.rpy.rpyToMatrix(0.3, 0, 0.5), np.array([1.0, 2, 3]))
    for body in ("ground", "Link2", "Tip"):
        expected = placement * pose_in(model, q, body)
        got = world.body_pose(f"arm_{body}", q_world)
        np.testing.assert_allclose(got.homogeneous, expected.homogeneous, atol=1e-9)


def test_two_namespaced_ur5s_do_not_overlap(tmp_path):
    world = load_world(write(tmp_path, "w.yaml", f"""
        models:
          - path: {UR5}
            namespace: left
            joint: {{position: {{linear: [0, 0.4, 0]}}}}
          - path: {UR5}
            namespace: right
            joint: {{position: {{linear: [0, -0.4, 0]}}}}
    """))
    q = world.neutral_configuration()
    links = [n[len("left_"):] for n in world.body_names() if n.startswith("left_")]
    assert "base_link" in links and "world" not in links
    for link in links:
        left = world.body_pose(f"left_{link}", q)
        right = world.body_pose(f"right_{link}", q)
        np.testing.assert_allclose(left.translation - right.translation, [0, 0.8, 0],
                                   atol=1e-12)
    assert world.body("left_base_link").parent == "world"


def test_unknown_parent_of_a_ur5_is_located(tmp_path):
    path = write(tmp_path, "w.yaml", f"""
        models:
          - path: robocop/body.urdf
            namespace: table
          - path: {UR5}
            namespace: ur5
            joint:
              parent: tabel_body
    """)
    with pytest.raises(DiagnosticError) as caught:
        load_world(path)
    [d] = caught.value.diagnostics
    assert (d.code, d.file, d.span.line, d.span.column) == ("unknown-parent", str(path), 7, 15)
    assert d.message == "unknown parent body 'tabel_body'"
    assert d.hint == "did you mean 'table_body'?"


def test_world_command_prints_placements(tmp_path, capsys):
    path = write(tmp_path, "w.yaml", UR5_ON_TABLE)
    assert main(["world", str(path), "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["units"] == {"position": "m", "rpy": "rad"}
    base = next(b for b in data["bodies"] if b["name"] == "ur5_base_link")
    np.testing.assert_allclose(base["position"], TABLE, atol=1e-12)
    np.testing.assert_allclose(base["rpy"], [0, 0, 0], atol=1e-12)
    assert main(["world", str(path)]) == 0
    out = capsys.readouterr().out
    assert "position [m], rpy [deg]" in out
    assert "ur5_base_link  (fixed table_body_to_ur5_base_link)  [0.500, 0.200, 0.800]" in out


def test_world_link_with_two_joints_is_an_error(tmp_path):
    urdf = write(tmp_path, "two.urdf", """
        <robot name="two">
          <link name="world"/>
          <link name="a"/>
          <link name="b"/>
          <joint name="to_a" type="fixed"><parent link="world"/><child link="a"/></joint>
          <joint name="to_b" type="fixed"><parent link="world"/><child link="b"/></joint>
        </robot>
    """)
    path = write(tmp_path, "w.yaml", f"""
        models:
          - path: {urdf}
    """)
    with pytest.raises(DiagnosticError) as caught:
        load_world(path)
    [d] = caught.value.diagnostics
    assert (d.code, d.file, d.span.line) == ("urdf-error", str(urdf), 2)
    assert "'world' link" in d.message and "joint:" in d.hint


def test_moving_joint_keeps_its_axis_in_the_joint_frame(tmp_path):
    """A rail along x under TwoDofs, whose own base is turned by -1.57 rad."""
    world = load_world(write(tmp_path, "w.yaml", f"""
        models:
          - path: {TWO_DOFS}
            namespace: arm
            joint:
              type: prismatic
              axis: [1, 0, 0]
              limits: {{lower: -1, upper: 1, velocity: 0.5}}
    """))
    rail = world.joint_group("world_to_arm_ground")
    q = world.neutral_configuration()
    q[rail.q_indices] = 0.3
    ground = world.body_pose("arm_ground", q)
    np.testing.assert_allclose(ground.translation, [0.3, 0, 0], atol=1e-12)
    np.testing.assert_allclose(ground.rotation, pin.rpy.rpyToMatrix(0, 0, -1.57), atol=1e-12)
