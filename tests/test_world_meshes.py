"""Mesh files a URDF names: refused unless a regular file with a mesh extension, and a
collision mesh that coal's loader cannot load is a located ``mesh-error`` in every
command, never a traceback."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from robocop_dsl.compile import WorldCache, check_file
from robocop_dsl.diagnostics import DiagnosticError
from robocop_dsl.world import load_world

from conftest import AVOIDING_MISSION, ONE_LINK_ARM, write

REPO = Path(__file__).resolve().parent.parent
WORLDS = REPO / "tests" / "fixtures" / "worlds"
TETRAHEDRON = """solid t
facet normal 0 0 -1
outer loop
vertex 0 0 0
vertex 0 1 0
vertex 1 0 0
endloop
endfacet
facet normal 0 -1 0
outer loop
vertex 0 0 0
vertex 1 0 0
vertex 0 0 1
endloop
endfacet
facet normal -1 0 0
outer loop
vertex 0 0 0
vertex 0 0 1
vertex 0 1 0
endloop
endfacet
facet normal 1 1 1
outer loop
vertex 1 0 0
vertex 0 1 0
vertex 0 0 1
endloop
endfacet
endsolid t
"""
LFS_POINTER = ("version https://git-lfs.github.com/spec/v1\n"
               "oid sha256:4d7a214614ab2935c943f9e0ff69d22eadbb8f32b1258daaa5e2ca24d17e2393\n"
               "size 12345\n")


@pytest.fixture(autouse=True)
def _private_cache(tmp_path, monkeypatch):
    """What the loader said is kept in a cache folder of the test's own."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))


def arm_world(folder: Path, mesh: str, kind: str = "collision") -> Path:
    write(folder, "arm.urdf", ONE_LINK_ARM.format(
        element=f'<{kind}><geometry><mesh filename="{mesh}"/></geometry></{kind}>'))
    write(folder, "m.mission", AVOIDING_MISSION)
    return write(folder, "w.yaml", "models:\n  - path: arm.urdf\n")


def cli(*args, cwd: Path):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd, check=False,
                          env={**os.environ, "PYTHONPATH": str(REPO)})


def the_error(path: Path):
    with pytest.raises(DiagnosticError) as caught:
        load_world(path)
    [diagnostic] = caught.value.diagnostics
    return diagnostic


def test_a_collision_mesh_of_random_bytes_is_located_in_every_command(tmp_path):
    shutil.copy(WORLDS / "garbage.stl", tmp_path / "garbage.stl")
    arm_world(tmp_path, "garbage.stl")
    located = (f"{tmp_path / 'arm.urdf'}:4:32: error[mesh-error]: cannot load mesh "
               "'garbage.stl' of link 'l3': Failed to determine STL storage representation "
               "for garbage.stl.")
    for command, target, code in (("check", "m.mission", 1), ("world", "w.yaml", 1),
                                  ("run", "m.mission", 2)):
        done = cli(command, target, cwd=tmp_path)
        output = done.stdout + done.stderr
        assert done.returncode == code, output
        assert "Traceback" not in output
        assert located in output.splitlines()
        assert "   | " + " " * 31 + "^" * len('filename="garbage.stl"') in output
        assert "= hint: a mesh is a regular file in STL" in output


def test_a_git_lfs_pointer_in_place_of_the_mesh_is_named_so(tmp_path):
    (tmp_path / "link.stl").write_text(LFS_POINTER)
    error = the_error(arm_world(tmp_path, "link.stl"))
    assert (error.code, error.span.line, error.span.column) == ("mesh-error", 4, 32)
    assert error.message.startswith("cannot load mesh 'link.stl' of link 'l3': ")
    assert error.hint == "the file is a Git LFS pointer, not the mesh: fetch it with 'git lfs pull'"


@pytest.mark.parametrize("mesh, reason", [
    ("/etc/passwd", "not a mesh file (the name must end with .stl, .dae, .obj, .ply, .msh)"),
    ("/dev/zero", "not a mesh file (the name must end with .stl, .dae, .obj, .ply, .msh)"),
    ("zero.stl", "it links to a file whose name does not end with .stl, .dae, .obj, .ply, "
                 ".msh"),
    ("fifo.stl", "not a regular file"),
    ("folder.stl", "not a regular file"),
])
def test_a_mesh_that_is_not_a_mesh_file_is_refused_unread(tmp_path, mesh, reason):
    """Visual meshes too: the file is never opened, and nothing of it is quoted."""
    (tmp_path / "zero.stl").symlink_to("/dev/zero")
    os.mkfifo(tmp_path / "fifo.stl")
    (tmp_path / "folder.stl").mkdir()
    for kind in ("collision", "visual"):
        error = the_error(arm_world(tmp_path, mesh, kind))
        assert (error.code, error.span.line, error.span.column) == ("mesh-error", 4,
                                                                    len(kind) + 23)
        assert error.message == f"cannot read mesh '{mesh}' of link 'l3': {reason}"


def test_a_missing_mesh_is_located_at_its_filename(tmp_path):
    error = the_error(arm_world(tmp_path, "package://arm/link.stl"))
    assert (error.code, error.span.line, error.span.column) == ("mesh-not-found", 4, 32)
    assert error.span.end_column - error.span.column == len('filename="package://arm/link.stl"')


def test_the_check_of_a_mission_reports_the_mesh_and_not_a_body_without_geometry(tmp_path):
    (tmp_path / "garbage.stl").write_bytes(bytes(range(256)) * 2)
    arm_world(tmp_path, "garbage.stl")
    found = check_file(tmp_path / "m.mission", cache=WorldCache(), compiled=False)
    assert [d.code for d in found.diagnostics] == ["world-error", "mesh-error"]


def test_a_mesh_that_loads_gives_its_body_collision_geometry(tmp_path):
    (tmp_path / "tetra.stl").write_text(TETRAHEDRON)
    arm_world(tmp_path, "tetra.stl")
    done = cli("world", "w.yaml", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert "l3: convex hull of 4 points" in done.stdout


def test_a_world_loaded_again_does_not_load_its_meshes_again(tmp_path):
    """What the loader said is read back from the cache: coal is not
    imported by the second load."""
    (tmp_path / "tetra.stl").write_text(TETRAHEDRON)
    world = arm_world(tmp_path, "tetra.stl")
    probe = ("import sys\nfrom robocop_dsl.world import load_world\n"
             f"load_world({str(world)!r})\n"
             "print(sorted(m for m in ('coal', 'pinocchio') if m in sys.modules))\n")
    runs = [subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                           check=False, env={**os.environ, "PYTHONPATH": str(REPO)})
            for _ in range(2)]
    assert [run.stdout.strip() for run in runs] == ["['coal']", "[]"], \
        runs[0].stderr + runs[1].stderr
