"""Static checks of a parsed mission against its world, every problem in one pass."""

from __future__ import annotations

import networkx as nx

from ..diagnostics import SourceFile
from ..lang import ast
from .context import CheckContext
from .controllers import check_assignment
from .declarations import check_controller, check_declarations, check_header, collect_symbols
from .graph_checks import check_state_graph
from .states import check_start, check_states, start_state


def check_mission(mission: ast.Mission, source: SourceFile, world=None) -> CheckContext:
    """Check names, types, parameters, units, targets, states and actions.

    ``world`` is the loaded :class:`~robocop_dsl.world.World`, or ``None`` when it could
    not be loaded (checks that need its names are then skipped). The returned context
    holds the diagnostics and the mission's symbols, for :func:`check_graph`.
    """
    ctx = CheckContext(source, world)
    collect_symbols(ctx, mission)
    check_header(ctx, mission)
    check_controller(ctx, mission)
    check_declarations(ctx, mission)
    check_assignment(ctx, mission)
    check_start(ctx, mission)
    check_states(ctx, mission)
    ctx.expanded = mission
    return ctx


def check_graph(ctx: CheckContext, mission: ast.Mission, graph: nx.DiGraph) -> None:
    """Add the state-graph checks (reachability, shadowed clauses...) to ``ctx``."""
    check_state_graph(ctx, mission, graph)


def first_state(ctx: CheckContext, mission: ast.Mission) -> str | None:
    """The state the mission starts in, if it is a declared state."""
    return start_state(ctx, mission)
