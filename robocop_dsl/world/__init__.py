"""World descriptions: YAML files composing URDF models with namespaces and joints."""

from .assembly import BodyInfo
from .paths import resolve_world_path, robots_path
from .urdf import JointInfo
from .processors import Processor
from .world import JointGroup, World, load_world

__all__ = ["World", "JointGroup", "JointInfo", "BodyInfo", "Processor", "load_world",
           "resolve_world_path", "robots_path"]
