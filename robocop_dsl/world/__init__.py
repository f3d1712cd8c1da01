"""World descriptions: YAML files composing URDF models with namespaces and joints."""

from .assembly import BodyInfo
from .paths import resolve_world_path, robots_path
from .urdf import JointInfo
from .world import JointGroup, Processor, World, load_world

__all__ = ["World", "JointGroup", "JointInfo", "BodyInfo", "Processor", "load_world",
           "resolve_world_path", "robots_path"]
