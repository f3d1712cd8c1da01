"""The MuJoCo model of a world, read back by MuJoCo's own loader from the MJCF that
``robocop-mission world --mjcf`` writes, and the located errors of worlds physics
cannot simulate."""

import json
import subprocess
import sys
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from conftest import write
from robocop_dsl.cli.main import main
from robocop_dsl.diagnostics import DiagnosticError
from robocop_dsl.physics.model import physics_model
from robocop_dsl.world import load_world

REPO = Path(__file__).resolve().parent.parent


def cli(*args):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", *map(str, args)],
                          capture_output=True, text=True, cwd=REPO)


@pytest.fixture(scope="module")
def pick():
    return load_world("panda/panda_pick.yaml")


@pytest.fixture(scope="module")
def pick_mjcf(tmp_path_factory):
    """MuJoCo's own model and data of the MJCF written by the command line, at its
    ``initial`` keyframe."""
    out = tmp_path_factory.mktemp("mjcf") / "pick.xml"
    done = cli("world", "panda/panda_pick.yaml", "--mjcf", out)
    assert done.returncode == 0, done.stderr
    model = mujoco.MjModel.from_xml_path(str(out))
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("initial").id)
    mujoco.mj_forward(model, data)
    return model, data


def body_poses(model, data) -> dict:
    return {model.body(i).name: pin.XYZQUATToSE3(np.r_[data.xpos[i], data.xquat[i][1:],
                                                       data.xquat[i][:1]])
            for i in range(1, model.nbody)}


@pytest.mark.parametrize("path", ["panda/panda_pick.yaml", "bazar/sophia_physics.yaml"])
def test_every_body_is_where_pinocchio_puts_it(path):
    """At the initial configuration, each URDF link is a MuJoCo body at the pose
    pinocchio computes from the same world (placements, namespaces, parents)."""
    world = load_world(path)
    physics = physics_model(world, 0.001)
    from robocop_dsl.physics.model import initial_state

    data = mujoco.MjData(physics.model)
    data.qpos[:], data.act[:] = initial_state(physics, world, world.initial_configuration())
    mujoco.mj_forward(physics.model, data)
    expected = world.body_placements(world.initial_configuration())
    found = body_poses(physics.model, data)
    assert set(found) == set(expected) - {"world"}
    for body, pose in expected.items():
        if body != "world":
            assert np.allclose(found[body].homogeneous, pose.homogeneous, atol=1e-9), body


def test_the_mjcf_has_the_worlds_joints_inertias_and_contacts(pick, pick_mjcf):
    model, data = pick_mjcf
    names = {model.joint(i).name: model.jnt_type[i] for i in range(model.njnt)}
    assert names["panda_joint1"] == mujoco.mjtJoint.mjJNT_HINGE
    assert names["panda_finger_joint1"] == mujoco.mjtJoint.mjJNT_SLIDE
    assert names["cube_body_free"] == mujoco.mjtJoint.mjJNT_FREE
    assert np.isclose(model.body("cube_body").mass[0], 0.1)
    assert np.isclose(model.body("panda_link1").mass[0], 4.970684)
    assert np.allclose(model.opt.gravity, [0, 0, -9.81])
    assert np.allclose(model.geom("cube_body_collision_0").friction, [1.0, 0.005, 0.0001])
    assert np.allclose(model.geom("cube_body_collision_0").size, [0.02, 0.02, 0.02])
    assert model.jnt_range[model.joint("panda_joint4").id].tolist() == [-3.0718, -0.0698]
    # adjacent links and the SRDF's pairs never touch; the cube touches everything
    excluded = {frozenset((model.body(a).name, model.body(b).name))
                for a, b in (divmod(e, 1 << 16) for e in model.exclude_signature)}
    assert frozenset(("panda_hand", "panda_leftfinger")) in excluded
    assert frozenset(("panda_leftfinger", "panda_rightfinger")) in excluded
    assert not any("cube_body" in pair for pair in excluded)
    # the mimic finger follows the first one
    (mimic,) = [i for i in range(model.neq) if model.eq_type[i] == mujoco.mjtEq.mjEQ_JOINT]
    assert model.joint(model.eq_obj1id[mimic]).name == "panda_finger_joint2"
    assert model.joint(model.eq_obj2id[mimic]).name == "panda_finger_joint1"
    # the initial keyframe: the world's initial posture, fingers open, cube on the table
    q0 = pick.initial_configuration()
    arm = pick.joint_group("panda_arm")
    assert np.allclose(data.qpos[:7], q0[arm.q_indices])
    assert np.allclose(data.qpos[7:9], [0.04, 0.04])
    assert np.allclose(data.xpos[model.body("cube_body").id], [0.5, 0.0, 0.77])


def test_the_mjcf_uses_the_drivers_step_and_gains(pick_mjcf):
    model, _ = pick_mjcf
    assert model.opt.timestep == 0.001
    servo = model.actuator("panda_joint1_target")
    assert servo.gainprm[0] == 2000.0 and servo.biasprm[1] == -2000.0
    assert model.actuator("panda_joint1_velocity").gainprm[0] == 100.0


def test_physics_section_of_the_world_file(tmp_path):
    world = write(tmp_path, "moon.yaml", """
        models:
          - include: panda/panda_pick.yaml
        physics:
          gravity: [0, 0, -1.62]
          friction: 0.4
    """)
    loaded = load_world(world)
    assert loaded.physics.gravity == (0.0, 0.0, -1.62)
    assert loaded.physics.friction == (0.4, 0.005, 0.0001)
    model = physics_model(loaded).model
    assert np.allclose(model.opt.gravity, [0, 0, -1.62])
    assert np.allclose(model.geom_friction[:, 0], 0.4)
    described = json.loads(cli("world", world, "--format", "json").stdout)
    assert described["physics"] == {"gravity": [0.0, 0.0, -1.62],
                                    "friction": [0.4, 0.005, 0.0001],
                                    "free_bodies": ["cube_body"]}


def test_physics_errors_are_located(tmp_path):
    """A negative friction, a misspelt key, free with a joint type: each at its place."""
    world = write(tmp_path, "w.yaml", """
        models:
          - path: panda/cube.urdf
            free: true
            joint: {type: revolute, limits: {lower: 0, upper: 1, velocity: 1}}
        physics:
          friction: [-1]
          gravty: [0, 0, -9.81]
    """)
    with pytest.raises(DiagnosticError) as error:
        load_world(world)
    found = {(d.code, d.span.line, d.message) for d in error.value.diagnostics}
    assert ("invalid-entry", 3, "a free model cannot have a revolute joint") in found
    assert ("invalid-entry", 6, "'friction' must be 1 to 3 numbers >= 0") in found
    assert ("invalid-entry", 7, "unknown key 'gravty'") in found


def test_a_free_model_without_mass(tmp_path):
    """Physics moves a free body by its inertia: a URDF link without mass is refused,
    located at its <link> in the URDF, through the command line."""
    write(tmp_path, "massless.urdf", """
        <robot name="massless">
          <link name="body">
            <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
          </link>
        </robot>
    """)
    world = write(tmp_path, "w.yaml", """
        models:
          - path: massless.urdf
            namespace: thing
            free: true
            joint: {position: {linear: [0, 0, 1]}}
    """)
    done = cli("world", world, "--mjcf", tmp_path / "out.xml")
    assert done.returncode == 1 and "Traceback" not in done.stderr
    assert done.stderr.splitlines()[:3] == [
        f"{tmp_path / 'massless.urdf'}:2:3: error[physics-error]: the free model's link "
        "'thing_body' has no mass",
        ' 2 |   <link name="body">',
        "   |   ^^^^^",
    ]
    assert not (tmp_path / "out.xml").exists()


_PLY = """ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
element face 4
property list uchar int vertex_indices
end_header
0 0 0
0.1 0 0
0 0.1 0
0 0 0.1
3 0 2 1
3 0 1 3
3 0 3 2
3 1 2 3
"""


def meshy_world(folder: Path, mesh: str, text: str) -> Path:
    """A world of one link whose collision mesh is ``mesh``, holding ``text``."""
    (folder / mesh).write_text(text)
    write(folder, "meshy.urdf", f"""
        <robot name="meshy">
          <link name="base"/>
          <link name="body">
            <inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1"/></inertial>
            <collision><geometry><mesh filename="{mesh}"/></geometry></collision>
          </link>
          <joint name="j" type="revolute">
            <parent link="base"/><child link="body"/>
            <limit lower="-1" upper="1" velocity="1" effort="1"/>
          </joint>
        </robot>
    """)
    return write(folder, "w.yaml", "models:\n  - path: meshy.urdf\n")


def test_a_mesh_mujoco_cannot_read(tmp_path):
    """A collision mesh in a format MuJoCo does not read (PLY, which the collision
    geometry's loader reads): an error at the link that uses it."""
    world = load_world(meshy_world(tmp_path, "shape.ply", _PLY))
    with pytest.raises(DiagnosticError) as error:
        physics_model(world)
    (diagnostic,) = error.value.diagnostics
    assert diagnostic.code == "physics-error"
    assert Path(diagnostic.file).name == "meshy.urdf" and diagnostic.span.line == 3
    assert "cannot read the collision mesh 'shape.ply' of link 'body'" in diagnostic.message


@pytest.mark.parametrize("mesh, text", [("shape.dae", "<COLLADA/>"),
                                        ("shape.stl", "not an STL file")])
def test_a_broken_mesh_is_an_error_of_the_world(tmp_path, mesh, text):
    """A collision mesh that no loader reads is an error where the URDF names it, as
    the world loads (before any physics)."""
    with pytest.raises(DiagnosticError) as error:
        load_world(meshy_world(tmp_path, mesh, text))
    (diagnostic,) = error.value.diagnostics
    assert diagnostic.code == "mesh-error"
    assert Path(diagnostic.file).name == "meshy.urdf" and diagnostic.span.line == 5
    assert f"cannot load mesh '{mesh}' of link 'body'" in diagnostic.message


def test_driver_options_are_checked_with_the_world(tmp_path):
    """A misspelt option, a step that does not divide the period, gains of the wrong
    length and a group the controller does not command: located, all at once."""
    world = write(tmp_path, "w.yaml", """
        models:
          - include: panda/panda_on_table.yaml
          - path: panda/cube.urdf
            namespace: cube
            free: true
            joint: {position: {linear: [0.5, 0, 0.77]}}
        joint_groups:
          panda_all: [panda_arm, panda_gripper]
        processors:
          controller:
            type: qp_controller
            options: {joint_group: panda_arm, time_step: 10ms}
          driver:
            type: mujoco
            options: {joint_group: panda_all, time_step: 3ms, gains: {kp: [1, 2]},
                      tiem_step: 1ms}
    """)
    assert main(["world", str(world)]) == 1
    with pytest.raises(DiagnosticError) as error:
        load_world(world)
    found = {(d.code, d.span.line, d.span.column, d.message) for d in error.value.diagnostics}
    assert found == {
        ("unknown-option", 16, 15, "unknown option 'tiem_step' of a mujoco processor"),
        ("wrong-option", 15, 28, "driver 'driver' drives joints no controller commands: "
                                 "panda_finger_joint1, panda_finger_joint2"),
        ("wrong-option", 15, 67, "gains: 'kp' has 2 values, the joint group 'panda_all' "
                                 "has 8 joints"),
        ("wrong-option", 15, 50, "the physics step 3 ms of 'driver' does not divide the "
                                 "period 10 ms of 'controller'"),
    }


def test_a_variant_overrides_what_it_includes(tmp_path):
    """A file's processors override those of its includes, however deep: the variant of
    the pick world keeps the pick's controller on the fingers and arm, with its own
    driver."""
    world = load_world(write(tmp_path, "kinematic.yaml", """
        models:
          - include: panda/panda_pick.yaml
        processors:
          driver: {type: simulated, options: {joint_group: panda_all}}
    """))
    assert world.processors["controller"].options["joint_group"] == "panda_all"
    assert world.processors["driver"].type == "simulated"
    assert world.physics.friction == (1.0, 0.005, 0.0001)


def test_check_against_a_world_variant(tmp_path):
    """`check --world`: the pickup passes on its physics variant, and a variant whose
    part is not free gets every attach and detach located."""
    assert cli("check", "missions/pickup.mission", "--world",
               "bazar/sophia_physics.yaml").returncode == 0
    fixed = write(tmp_path, "fixed_part.yaml", """
        models:
          - include: bazar/sophia.yaml
        processors:
          driver: {type: mujoco, options: {joint_group: bazar_upper_joints}}
    """)
    done = cli("check", "missions/pickup.mission", "--world", fixed)
    assert done.returncode == 1
    assert [line.split(": error")[0].rsplit(":", 2)[1:] for line in done.stdout.splitlines()
            if "error[not-free]" in line] == [["67", "39"], ["83", "43"]]
