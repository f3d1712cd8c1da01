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
