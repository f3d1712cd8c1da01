"""The composed world as one URDF for ``/robot_description``: every model of the world
under its ``world`` link, meshes referenced by ``file://`` URIs of their absolute paths
(what Foxglove and RViz load without a ROS package path)."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path


def robot_description(world) -> str:
    """The URDF of ``world`` (a :class:`~robocop_dsl.world.World`), meshes as
    ``file://`` URIs."""
    robot = ET.fromstring(world.urdf)
    for mesh in robot.iter("mesh"):
        filename = mesh.get("filename", "")
        if "://" not in filename:
            mesh.set("filename", Path(filename).resolve().as_uri())
    return ET.tostring(robot, encoding="unicode")
