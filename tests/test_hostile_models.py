"""Inputs that used to end in a Python traceback, through the command line: URDF
numbers with units or NaN, a negative velocity limit, a joint type URDF does not have,
a chain of 300 behaviours, a campaign of a million samples or of infinite duration.
Each is now a located diagnostic."""

import subprocess
import sys
from pathlib import Path

import pytest

from conftest import write

REPO = Path(__file__).resolve().parent.parent
ARM = """
    <robot name="arm">
      <link name="base"/>
      <link name="l1"/>
      <joint name="j1" type="{type}">
        <parent link="base"/><child link="l1"/><axis xyz="{axis}"/>
        <limit lower="-1" upper="{upper}" velocity="{velocity}" effort="1"/>
      </joint>
    </robot>
"""


def cli(*args, cwd=REPO):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd)


def driven_arm(tmp_path, models: str, group: str, joint: str, task: str, target: str,
               limits: str) -> tuple:
    """``w.yaml`` (``models`` lines, the group of ``joint``, a controller and a simulated
    driver on it) and ``m.mission``, which moves the ``task`` to ``target`` with an otg
    of ``limits``: their paths."""
    world = write(tmp_path, "w.yaml", "\n        models:\n" + models + f"""
        joint_groups:
          {group}: [{joint}]
        processors:
          controller:
            type: qp_controller
            options: {{joint_group: {group}, time_step: 5ms}}
          sim:
            type: simulated
            options: {{joint_group: {group}}}
    """)
    mission = write(tmp_path, "m.mission", f"""
        mission m
        world "w.yaml"
        task t: {task} {{
            interpolator = otg({limits})
        }}
        start s
        state s {{
            enter {{
                enable t
                t.target = {target}
            }}
            when t.reached -> done
        }}
        final done
    """)
    return world, mission


@pytest.mark.parametrize("joint, message, column", [
    ({"upper": "2.775mm"}, "'upper' of the <limit> of joint 'j1' must be a finite number, "
                           "not '2.775mm'", 23),
    ({"upper": "nan"}, "'upper' of the <limit> of joint 'j1' must be a finite number, "
                       "not 'nan'", 23),
    ({"velocity": "-2"}, "'velocity' of the <limit> of joint 'j1' is negative: -2", 33),
    ({"type": "revolve"}, "joint 'j1' has no URDF type 'revolve'", 20),
    ({"upper": "1 "}, "'upper' of the <limit> of joint 'j1' must be a finite number, "
                      "not '1 '", 23),
    ({"upper": "1&#10;"}, "'upper' of the <limit> of joint 'j1' must be a finite number, "
                          r"not '1\n'", 23),
    ({"upper": "\uff11"}, "'upper' of the <limit> of joint 'j1' must be a finite number, "
                          r"not '\uff11'", 23),
    ({"upper": "&#9;1"}, None, 0),
    ({"axis": "0&#9;0 1"}, "'xyz' of the <axis> of joint 'j1' must be three finite numbers, "
                           r"not '0\t0 1'", 50),
])
def test_bad_urdf_numbers_and_types_are_located(tmp_path, joint, message, column):
    """Each used to pass as a number or a type, then pinocchio's URDF parser (urdfdom)
    refused the file and ``world`` and ``run`` ended in a traceback."""
    values = {"type": "revolute", "upper": "1", "velocity": "1", "axis": "0 0 1", **joint}
    write(tmp_path, "arm.urdf", ARM.format(**values))
    world = write(tmp_path, "w.yaml", "models:\n  - path: arm.urdf\n")
    done = cli("world", world)
    if message is None:             # blanks before a number: urdfdom reads it
        assert done.returncode == 0, done.stderr
        return
    assert done.returncode == 1 and "Traceback" not in done.stderr
    line = {"type": 4, "axis": 5}.get(next(iter(joint)), 6)
    assert done.stderr.splitlines()[0] == (
        f"{tmp_path / 'arm.urdf'}:{line}:{column}: error[urdf-error]: {message}")


@pytest.mark.parametrize("joint, message, line, column", [
    ('<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/></joint>',
     "revolute joint 'j1' has no <limit>", 5, 1),
    ('<joint name="j1" type="prismatic"><parent link="base"/><child link="l1"/>\n'
     '<limit lower="0" upper="1" effort="1"/></joint>',
     "the <limit> of joint 'j1' has no 'velocity'", 6, 1),
    ('<joint name="j1" type="continuous"><parent link="base"/><child link="l1"/>\n'
     '<limit velocity="1"/></joint>', "the <limit> of joint 'j1' has no 'effort'", 6, 1),
    ('<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>\n'
     '<axis xyz="0 0 0"/><limit lower="0" upper="1" velocity="1" effort="1"/></joint>',
     "joint 'j1' has a zero axis", 6, 7),
    ('<joint name="j1" type="fixed"><parent link="base"/><child link="l1"/></joint>\n'
     '<link name="l1"/>', "two links are named 'l1'", 6, 7),
    ('<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>\n'
     '<origin xyz="0 0 0.1"/><axis xyz="0&#9;0 1"/>\n'
     '<limit lower="0" upper="1" velocity="1" effort="1"/></joint>',
     r"'xyz' of the <axis> of joint 'j1' must be three finite numbers, not '0\t0 1'", 6, 30),
    ('<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>\n'
     '<dynamics damping="0.1 "/><limit lower="0" upper="1" velocity="1" effort="1"/></joint>',
     "'damping' of the <dynamics> of joint 'j1' must be a finite number, not '0.1 '", 6, 11),
])
def test_urdfs_that_urdf_parsers_refuse_are_refused_first(tmp_path, joint, message, line,
                                                          column):
    """What urdfdom (under pinocchio) refuses used to pass ``check`` and end ``run`` and
    ``world`` in a traceback."""
    write(tmp_path, "arm.urdf", f'<robot name="arm">\n<link name="base"/>\n'
                                f'<link name="l1"/>\n\n{joint}\n</robot>\n')
    world = write(tmp_path, "w.yaml", "models:\n  - path: arm.urdf\n")
    mission = write(tmp_path, "m.mission", 'mission m\nworld "w.yaml"\nstart s\n'
                                           "state s {\n    when elapsed > 1 s -> done\n}\n"
                                           "final done\n")
    for command in ("world", "check", "run"):
        done = cli(command, world if command == "world" else mission)
        assert done.returncode in (1, 2) and "Traceback" not in done.stderr + done.stdout
        assert (f"{tmp_path / 'arm.urdf'}:{line}:{column}: error[urdf-error]: {message}"
                in done.stdout + done.stderr)


def test_a_chain_of_300_behaviours(tmp_path):
    lines = ['mission chain "Each behaviour runs the next."',
             'world "panda/panda_on_table.yaml"']
    for index in range(300):
        inner = (f"state s: b{index + 1}()\n    when s.f -> f" if index < 299
                 else "state s {\n        when elapsed > 1 s -> f\n    }")
        lines.append(f"behavior b{index}() {{\n    {inner}\n    final f\n}}")
    lines.append("state top: b0() {\n    when top.f -> done\n}\nfinal done\n")
    mission = tmp_path / "chain.mission"
    mission.write_text("\n".join(lines))
    done = cli("check", mission)
    assert done.returncode == 1 and "Traceback" not in done.stdout + done.stderr
    assert "error[nesting-too-deep]: behaviour instances nest more than 24 deep here" \
        in done.stdout


def test_a_campaign_too_large_or_too_long(tmp_path):
    campaign = write(tmp_path, "big.campaign.yaml", f"""
        missions: [{REPO / 'missions' / 'panda_reach.mission'}]
        samples: 1000000
        duration: 1e309 s
    """)
    done = cli("sweep", campaign)
    assert done.returncode == 2 and "Traceback" not in done.stderr
    errors = [line for line in done.stderr.splitlines() if "error[" in line]
    assert errors == [
        f"{campaign}:2:10: error[wrong-value]: 'samples' is 1,000,000: at most 100,000",
        f"{campaign}:3:11: error[wrong-value]: 'duration' must be at most a day (86400 s), "
        "not inf s"]


def test_a_campaign_time_step_too_short_to_be_meant_is_refused(tmp_path):
    """A campaign's ``time_step: 1e-12 s`` was accepted and its job crawled for good."""
    campaign = write(tmp_path, "ts.campaign.yaml", f"""
        missions: [{REPO / 'missions' / 'panda_reach.mission'}]
        samples: 1
        settings:
          time_step: [5ms, 1e-12 s]
    """)
    done = cli("sweep", "--serial", "-o", tmp_path / "out.parquet", campaign)
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert (f"{campaign}:4:20: error[wrong-value]: 'time_step' must be at least 10us, "
            "not 1e-12 s") in done.stderr
    assert not (tmp_path / "out.parquet").exists()


def test_a_time_step_too_short_to_be_meant_is_refused(tmp_path):
    """A controller period of 1e-12 s passed ``check`` and made ``run`` crawl forever."""
    world = write(tmp_path, "w.yaml", "models:\n  - include: panda/panda_on_table.yaml\n"
                                      "processors:\n  ctl:\n    type: qp_controller\n"
                                      "    options: {joint_group: panda_arm, "
                                      "time_step: 1e-12s}\n")
    done = cli("world", world)
    assert done.returncode == 1 and "Traceback" not in done.stderr
    assert "'time_step' must be at least 10us, not 1e-12s" in done.stderr


def test_limits_as_large_as_a_float_print_no_numpy_warning(tmp_path):
    """URDF limits of 1e308 are numbers like any other: ``world`` prints them unbounded
    and a run bounds its commands without an overflow warning on the terminal."""
    write(tmp_path, "arm.urdf", ARM.format(type="revolute", upper="1e308", velocity="1e308",
                                           axis="0 0 1").replace('lower="-1"', 'lower="-1e308"'))
    world, mission = driven_arm(tmp_path, "          - path: arm.urdf\n", "arm", "j1",
                                "joint_position(arm)", "[1] rad",
                                "max_velocity = 1 rad/s, max_acceleration = 1 rad/s^2")
    shown = cli("world", world)
    assert shown.returncode == 0 and "j1  revolute   unbounded" in shown.stdout
    done = cli("run", mission)
    assert done.returncode == 0 and "outcome: success" in done.stdout
    for output in (shown, done):
        assert "Warning" not in output.stderr, output.stderr


@pytest.mark.parametrize("groups, message", [
    ("hand_fixed: [panda_hand_joint]",
     "joint group 'hand_fixed' moves nothing: its joints are fixed or mimic others"),
    ("both: [panda_arm, cube_free]",
     "joint group 'both' holds the floating joint 'cube_free' (6 dofs): a joint group's "
     "joints move along or about one axis"),
])
def test_joint_groups_that_no_controller_can_command_are_world_errors(tmp_path, groups,
                                                                     message):
    """A group of fixed or mimic joints only, or one holding a free body's floating joint,
    gave tracebacks in ``world`` and ``run`` (and ``check`` passed)."""
    world = write(tmp_path, "w.yaml", f"""
        models:
          - include: panda/panda_on_table.yaml
          - path: panda/cube.urdf
            namespace: cube
            free: true
            joint: {{position: {{linear: [0.5, 0.0, 0.77]}}, name: cube_free}}
        joint_groups:
          {groups}
    """)
    mission = write(tmp_path, "m.mission", 'mission m\nworld "w.yaml"\nstart s\n'
                                           "state s {\n    when elapsed > 1 s -> done\n}\n"
                                           "final done\n")
    for command in ("world", "check", "run"):
        done = cli(command, world if command == "world" else mission)
        assert done.returncode in (1, 2) and "Traceback" not in done.stderr + done.stdout
        assert (f"{world}:8:3: error[invalid-entry]: {message}"
                in done.stdout + done.stderr)


def test_a_body_task_in_a_world_of_one_dof(tmp_path):
    """One prismatic joint: pinocchio's 6 x 1 Jacobian comes back flat, and every body
    task faulted with an IndexError."""
    _, mission = driven_arm(
        tmp_path, "          - path: robocop/point.urdf\n          - path: robocop/body.urdf\n"
                  "            joint: {parent: point, type: prismatic, axis: [1, 0, 0],\n"
                  "                    limits: {lower: -1, upper: 1, velocity: 1}}\n",
        "g", "point_to_body", "body_pose(body)", "pose(position = [0.2, 0, 0] m)",
        "max_velocity = 0.1 m/s, max_acceleration = 1 m/s^2")
    done = cli("run", mission)
    assert done.returncode == 0 and "outcome: success" in done.stdout, done.stdout


def test_a_zero_axis_in_a_world_file_is_located(tmp_path):
    """As a URDF's zero axis is: the run failed in MuJoCo's loader, or a body task
    faulted."""
    world = write(tmp_path, "w.yaml", """
        models:
          - path: robocop/point.urdf
          - path: robocop/body.urdf
            joint: {parent: point, type: prismatic, axis: [0, 0, 0],
                    limits: {lower: -1, upper: 1, velocity: 1}}
    """)
    done = cli("world", world)
    assert done.returncode == 1 and "Traceback" not in done.stderr
    assert done.stderr.splitlines()[0] == (
        f"{world}:4:45: error[invalid-entry]: 'axis' must not be zero")
