"""Static checks of a mission: names, types, units, targets and the state graph."""

from .checker import Cancelled, check_graph, check_mission
from .context import CheckContext, WorldNames
from .graph_checks import truth

__all__ = ["Cancelled", "check_graph", "check_mission", "CheckContext", "WorldNames",
           "truth"]
