"""Shared fixtures: the real bundled worlds, loaded once per test session."""

import textwrap
from pathlib import Path

import pytest

from robocop_dsl.world import load_world

REPO = Path(__file__).resolve().parent.parent
MISSIONS = REPO / "missions"


@pytest.fixture(scope="session")
def bazar():
    """The BAZAR pick-and-place world (bazar/sophia.yaml)."""
    return load_world("bazar/sophia.yaml")


@pytest.fixture(scope="session")
def panda():
    """A Panda from example-robot-data on a table (panda/panda_on_table.yaml)."""
    return load_world("panda/panda_on_table.yaml")


def write(folder, name, text):
    """Write ``text`` (dedented) to ``folder/name``, making folders; return the path."""
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(textwrap.dedent(text).lstrip("\n"))
    return path


ONE_LINK_ARM = """\
<robot name="arm">
  <link name="base"/>
  <link name="l3">
    {element}
  </link>
  <joint name="j3" type="fixed"><parent link="base"/><child link="l3"/></joint>
</robot>
"""
"""A URDF of a link 'l3' fixed to 'base', holding ``element`` (a visual or collision)."""
AVOIDING_MISSION = """\
mission m
world "w.yaml"
constraint clear: collision_avoidance(l3, base)
state s { when elapsed > 1 s -> done }
final done
"""
"""A mission keeping 'l3' clear of 'base' in the world 'w.yaml' beside it."""
