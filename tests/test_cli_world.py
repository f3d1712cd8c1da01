"""``robocop-mission world`` as a user calls it, and the installed wheel's contents."""

import json
import site
import subprocess
import sys
import sysconfig
import venv
import zipfile
from pathlib import Path

from robocop_dsl.cli.main import main

REPO = Path(__file__).resolve().parent.parent


def test_world_lists_the_application(capsys):
    assert main(["world", "bazar/sophia.yaml"]) == 0
    out = capsys.readouterr().out
    for name in ("bazar_left_hankamp_tool_object_side", "pickup_point", "drop_point"):
        assert f"    {name}  (fixed " in out
    assert "kinect2_link  (fixed bazar_ptu_mount_link_to_kinect2_link)" in out
    assert "  bazar_upper_joints: 16 dofs (" in out
    assert "  bazar_left_joint_2    revolute   [-120.0, 120.0] deg, 110.0 deg/s" in out


def test_world_json(capsys):
    assert main(["world", "bazar/sophia.yaml", "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    camera = next(b for b in data["bodies"] if b["name"] == "kinect2_link")
    assert camera["parent"] == "bazar_ptu_mount_link"
    groups = {g["name"]: g["dofs"] for g in data["joint_groups"]}
    assert groups["bazar_upper_joints"] == 16


def test_world_error_exit_code(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("models:\n  - path: robocop/point.urdf\n    joint: {parent: wrld}\n")
    done = subprocess.run([sys.executable, "-m", "robocop_dsl", "world", str(bad)],
                          capture_output=True, text=True)
    assert done.returncode == 1
    assert done.stdout == ""
    assert done.stderr.splitlines() == [
        f"{bad}:3:21: error[unknown-parent]: unknown parent body 'wrld'",
        " 3 |     joint: {parent: wrld}",
        "   |                     ^^^^",
        "   = hint: did you mean 'world'?",
    ]
    assert "Traceback" not in done.stderr


def test_a_file_that_is_no_world_is_refused_by_its_name():
    """A mission given as the world is refused for its name, not parsed as YAML."""
    done = subprocess.run([sys.executable, "-m", "robocop_dsl", "world",
                           str(REPO / "missions" / "pickup.mission")],
                          capture_output=True, text=True)
    assert done.returncode == 1 and done.stdout == ""
    assert "error[unreadable-file]" in done.stderr and "not a YAML file" in done.stderr
    assert "yaml-syntax" not in done.stderr and "Traceback" not in done.stderr


def test_usage_error_exit_code():
    done = subprocess.run([sys.executable, "-m", "robocop_dsl", "wrld"], capture_output=True,
                          text=True)
    assert done.returncode == 2 and "invalid choice" in done.stderr


PURELIB = "import sysconfig; print(sysconfig.get_paths()['purelib'])"


def test_installed_wheel_finds_grammar_and_robots(tmp_path):
    """A non-editable install run from another folder uses the files inside the wheel;
    its venv sees the running interpreter's packages (a venv's too) through a .pth."""
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w",
                    str(tmp_path / "dist"), str(REPO)], check=True)
    [wheel] = (tmp_path / "dist").glob("*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert "robocop_dsl/grammar/mission.lark" in names
    assert "robocop_dsl/robots/bazar/sophia.yaml" in names
    assert "robocop_dsl/robots/robocop/point.urdf" in names
    env_dir = tmp_path / "venv"
    venv.create(env_dir, with_pip=True)
    python = env_dir / "bin" / "python"
    inner = subprocess.run([python, "-c", PURELIB], capture_output=True, text=True,
                           check=True).stdout.strip()
    outer = dict.fromkeys([sysconfig.get_paths()["purelib"], *site.getsitepackages()])
    (Path(inner) / "outer_packages.pth").write_text(
        "".join(f"import site; site.addsitedir({p!r})\n" for p in outer))
    subprocess.run([python, "-m", "pip", "install", "-q", "--no-deps", str(wheel)], check=True)
    done = subprocess.run([env_dir / "bin" / "robocop-mission", "world", "bazar/sophia.yaml"],
                          cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "  bazar_upper_joints: 16 dofs" in done.stdout
    assert f"world {env_dir}" in done.stdout
