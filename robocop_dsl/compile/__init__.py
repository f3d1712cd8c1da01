"""Compiled missions: typed specs in SI, the state graph and its drawings.

The compiler and its specs are imported on first use, so that checking a mission (which
needs neither) does not pay for them.
"""

from .graph_render import to_dot, to_mermaid
from .load import CheckResult, WorldCache, check_file, check_source, load_mission
from .state_graph import build_state_graph

__all__ = ["compile_mission", "to_dot", "to_mermaid", "CheckResult", "WorldCache",
           "check_file", "check_source", "load_mission", "MissionSpec", "build_state_graph"]


def __getattr__(name: str):
    if name == "compile_mission":
        from .compiler import compile_mission

        return compile_mission
    if name == "MissionSpec":
        from .spec import MissionSpec

        return MissionSpec
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
