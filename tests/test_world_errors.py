"""Every world-file error is one located diagnostic: file, line, message, hint."""

import pytest

from robocop_dsl.diagnostics import DiagnosticError
from robocop_dsl.world import load_world

from conftest import write


def errors(path):
    with pytest.raises(DiagnosticError) as caught:
        load_world(path)
    return caught.value.diagnostics


def test_unknown_include(tmp_path):
    """An include that is nowhere on the robots path names the file and line."""
    path = write(tmp_path, "w.yaml", """
        models:
          - include: nowhere/missing.yaml
    """)
    [d] = errors(path)
    assert (d.code, d.file, d.span.line) == ("world-not-found", str(path), 2)
    assert d.message == "cannot find included world file 'nowhere/missing.yaml'"
    assert "ROBOCOP_PATH" in d.hint


def test_missing_urdf(tmp_path):
    path = write(tmp_path, "w.yaml", """
        models:
          - path: robocop/point.urdf
          - path: models/arm.urdf
    """)
    [d] = errors(path)
    assert (d.code, d.span.line, d.message) == ("urdf-not-found", 3, "cannot find URDF 'models/arm.urdf'")


def test_malformed_yaml(tmp_path):
    path = write(tmp_path, "w.yaml", """
        models:
          - path: robocop/point.urdf
            namespace: [a
    """)
    [d] = errors(path)
    assert d.code == "yaml-syntax" and d.span.line == 4
    assert d.message.startswith("malformed YAML")


def test_unknown_parent_with_suggestion(tmp_path):
    path = write(tmp_path, "w.yaml", """
        models:
          - path: robocop/point.urdf
            namespace: pickup
          - path: robocop/body.urdf
            namespace: part
            joint:
              parent: pickup_pont
    """)
    [d] = errors(path)
    assert (d.code, d.span.line, d.span.column) == ("unknown-parent", 7, 15)
    assert d.message == "unknown parent body 'pickup_pont'"
    assert d.hint == "did you mean 'pickup_point'?"
    assert d.render().splitlines()[1:3] == [
        " 7 |       parent: pickup_pont",
        "   |               ^^^^^^^^^^^",
    ]


def test_duplicate_names_after_namespacing(tmp_path):
    path = write(tmp_path, "w.yaml", """
        models:
          - path: robocop/point.urdf
            namespace: tip
          - path: robocop/point.urdf
            namespace: tip
    """)
    [d] = errors(path)
    assert (d.code, d.span.line) == ("duplicate-name", 4)
    assert d.message.startswith("body 'tip_point' of point.urdf is already defined")
    assert "namespace" in d.hint


def test_include_cycle(tmp_path):
    write(tmp_path, "b.yaml", """
        models:
          - include: a.yaml
    """)
    path = write(tmp_path, "a.yaml", """
        models:
          - include: b.yaml
    """)
    [d] = errors(path)
    assert d.code == "include-cycle" and d.file.endswith("b.yaml") and d.span.line == 2
    assert d.message == "include cycle: a.yaml -> b.yaml -> a.yaml"


def test_group_naming_unknown_joint(tmp_path):
    path = write(tmp_path, "w.yaml", """
        models:
          - include: bazar/fixed_bazar.yaml
            namespace: bazar
        joint_groups:
          head: [bazar_ptu_joint_pan, bazar_ptu_joint_tlt]
    """)
    [d] = errors(path)
    assert (d.code, d.span.line, d.span.column) == ("unknown-joint", 5, 31)
    assert d.message == "joint group 'head' names unknown joint or group 'bazar_ptu_joint_tlt'"
    assert d.hint == "did you mean 'bazar_ptu_joint_tilt'?"


def test_every_error_is_reported(tmp_path):
    """Several problems in one file give several diagnostics, not only the first."""
    path = write(tmp_path, "w.yaml", """
        models:
          - path: robocop/point.urdf
            namespace: a
            joint: {parent: nobody}
          - include: missing.yaml
        joint_groups:
          g: [no_joint]
    """)
    assert [d.code for d in errors(path)] == ["world-not-found", "unknown-parent", "unknown-joint"]


def test_malformed_urdf_names_the_urdf(tmp_path):
    write(tmp_path, "bad.urdf", """
        <robot name="bad">
          <link name="a">
        </robot>
    """)
    path = write(tmp_path, "w.yaml", """
        models:
          - path: bad.urdf
    """)
    [d] = errors(path)
    assert d.code == "urdf-error" and d.file.endswith("bad.urdf") and d.span.line == 3


def test_unknown_key_and_joint_type(tmp_path):
    path = write(tmp_path, "w.yaml", """
        models:
          - path: robocop/point.urdf
            namespce: a
            joint: {type: revolut}
    """)
    found = errors(path)
    assert [(d.code, d.span.line, d.hint) for d in found] == [
        ("invalid-entry", 3, "did you mean 'namespace'?"),
        ("invalid-entry", 4, "did you mean 'revolute'?"),
    ]


def test_missing_world_file():
    with pytest.raises(DiagnosticError) as caught:
        load_world("nowhere/world.yaml")
    [d] = caught.value.diagnostics
    assert d.code == "world-not-found" and d.message == "cannot find world file 'nowhere/world.yaml'"
