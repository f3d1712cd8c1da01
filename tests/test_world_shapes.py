"""Shapes URDF parsers would drop (urdfdom, under pinocchio, prints to stderr and leaves
the link without them) are a located ``urdf-error`` when the world loads."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import AVOIDING_MISSION, ONE_LINK_ARM, write

REPO = Path(__file__).resolve().parent.parent
OF = "of the <collision> of link 'l3'"


def cli(*args, cwd: Path):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd, check=False,
                          env={**os.environ, "PYTHONPATH": str(REPO)})


@pytest.mark.parametrize("shape, column, message", [
    ('<geometry><box size="-1 nan 0"/></geometry>', 31,
     f"'size' of the <box> {OF} must be three finite numbers, not '-1 nan 0'"),
    ('<geometry><box size="1 1"/></geometry>', 31,
     f"'size' of the <box> {OF} must be three finite numbers, not '1 1'"),
    ('<geometry><box size="1 0 1"/></geometry>', 31,
     f"'size' of the <box> {OF} must be above 0, not '1 0 1'"),
    ('<geometry><box/></geometry>', 26, f"the <box> {OF} has no 'size'"),
    ('<geometry><cylinder radius="0.1" length="-0.2"/></geometry>', 49,
     f"'length' of the <cylinder> {OF} must be above 0, not '-0.2'"),
    ('<geometry><sphere radius="inf"/></geometry>', 34,
     f"'radius' of the <sphere> {OF} must be a finite number, not 'inf'"),
    ('<geometry><capsule radius="0" length="1"/></geometry>', 35,
     f"'radius' of the <capsule> {OF} must be above 0, not '0'"),
    ('<geometry><cone radius="1"/></geometry>', 26,
     "<cone> in the <collision> of link 'l3' is not a URDF shape"),
    ('<geometry></geometry>', 16, f"the <geometry> {OF} holds no shape"),
    ('', 5, "the <collision> of link 'l3' has no <geometry>"),
    ('<geometry><mesh filename="a.stl" scale="1 nan 1"/></geometry>', 49,
     f"'scale' of the <mesh> {OF} must be three finite numbers, not '1 nan 1'"),
])
def test_a_shape_urdfdom_would_drop_is_located_in_every_command(tmp_path, shape, column,
                                                                 message):
    """Before, ``world`` said ``collision bodies (0)`` and ``check`` that 'l3' has no
    collision geometry, at the mission."""
    write(tmp_path, "arm.urdf", ONE_LINK_ARM.format(element=f"<collision>{shape}</collision>"))
    write(tmp_path, "w.yaml", "models:\n  - path: arm.urdf\n")
    write(tmp_path, "m.mission", AVOIDING_MISSION)
    for command, target, code in (("world", "w.yaml", 1), ("check", "m.mission", 1),
                                  ("run", "m.mission", 2)):
        done = cli(command, target, cwd=tmp_path)
        output = done.stdout + done.stderr
        assert done.returncode == code, output
        assert "Traceback" not in output and "no collision geometry" not in output
        located = [line for line in output.splitlines() if "[urdf-error]" in line]
        assert located == [f"{tmp_path / 'arm.urdf'}:4:{column}: error[urdf-error]: {message}"]
