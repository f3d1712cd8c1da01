"""Static checks of a parsed mission against its world, every problem in one pass."""

from __future__ import annotations

from pathlib import Path
from typing import Callable

import networkx as nx

from ..diagnostics import SourceFile
from ..lang import ast
from .context import CheckContext
from .controllers import check_assignment, check_driven
from .declarations import check_controller, check_declarations, check_header, collect_symbols
from .expand import Expander
from .graph_checks import check_behavior_graph, check_state_graph
from .imports import merge_imports
from .joint_limits import check_joint_limits, check_start_posture
from .joint_ranges import check_joint_ranges
from .regions import check_regions
from .states import check_machine, check_machines
from .variables import check_reads


class Cancelled(Exception):
    """A check stopped between two passes because its ``cancelled()`` turned true."""


def _never() -> bool:
    return False


def check_mission(mission: ast.Mission, source: SourceFile, world=None,
                  folder: Path | None = None,
                  cancelled: Callable[[], bool] = _never) -> CheckContext:
    """Check names, types, parameters, units, targets, machines and actions.

    ``world`` is the loaded :class:`~robocop_dsl.world.World`, or ``None`` when it could
    not be loaded (checks that need its names are then skipped); ``folder`` is where
    imports are looked up first. The returned context holds the diagnostics, the
    mission's symbols and its expanded tree (imports merged, constants bound, behaviour
    instances expanded), for :func:`check_graph` and the compiler.

    Raises:
        Cancelled: ``cancelled()`` was true between two passes (an editor's text
            changed meanwhile: what this check would find is of no use).
    """
    ctx = CheckContext(source, world)
    merged = merge_imports(ctx, mission, folder)
    collect_symbols(ctx, merged)
    check_header(ctx, mission)
    check_controller(ctx, merged)
    _stop_if(cancelled)
    expander = Expander(ctx, merged)
    expanded = expander.mission(merged)
    ctx.all_states = state_names(expanded.machine)
    _stop_if(cancelled)
    passes = (check_declarations, check_joint_ranges, check_joint_limits, check_start_posture,
              check_assignment, check_driven, check_machines)
    for check in passes:
        check(ctx, expanded)
        _stop_if(cancelled)
    check_reads(ctx, expanded.machine)
    check_regions(ctx, expanded.machine)
    base = ctx.generic
    ctx.variables = ctx.mission_variables
    for name, machine, generic in expander.unused_behaviors():
        _stop_if(cancelled)
        ctx.generic = generic
        ctx.all_states = state_names(machine)
        check_machine(ctx, machine, ())
        check_regions(ctx, machine)
        ctx.unused.append((expander.behaviors[name].name, machine))
    ctx.generic = base
    ctx.variables = {}
    ctx.expanded = expanded
    return ctx


def _stop_if(cancelled: Callable[[], bool]) -> None:
    if cancelled():
        raise Cancelled()


def state_names(machine: ast.Machine, owner: str | None = None,
                names: dict | None = None) -> dict[str, str | None]:
    """Every state name of a machine at any depth, with the state whose machine holds
    it (``None`` at the top; the first declaration of a name)."""
    names = {} if names is None else names
    for state in machine.states:
        names.setdefault(state.name.text, owner)
        for region in state.regions:
            if region.machine is not None:
                state_names(region.machine, state.name.text, names)
    return names


def check_graph(ctx: CheckContext, mission: ast.Mission, graph: nx.DiGraph,
                cancelled: Callable[[], bool] = _never) -> None:
    """Add the state-graph checks (reachability, shadowed clauses...) to ``ctx``, for
    the mission's machines and for the behaviours that no instance exposes; none when
    an imported file has a syntax error (a dropped statement would distort the graph).

    Raises:
        Cancelled: as :func:`check_mission`.
    """
    if not ctx.imports_parsed:
        return
    check_state_graph(ctx, mission, graph)
    for name, machine in ctx.unused:
        _stop_if(cancelled)
        check_behavior_graph(ctx, name, machine)
