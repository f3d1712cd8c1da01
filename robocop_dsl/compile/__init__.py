"""Compiled missions: typed specs in SI, the state graph and its drawings."""

from .compiler import compile_mission
from .graph_render import to_dot, to_mermaid
from .load import CheckResult, WorldCache, check_file, check_source, load_mission
from .spec import MissionSpec
from .state_graph import build_state_graph

__all__ = ["compile_mission", "to_dot", "to_mermaid", "CheckResult", "WorldCache",
           "check_file", "check_source", "load_mission", "MissionSpec", "build_state_graph"]
