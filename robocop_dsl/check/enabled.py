"""What may be enabled while a state's clauses are checked, on some path to it.

Per machine, parents first: a machine starts with what may be enabled inside its owner
state (the mission's with what is enabled from the start: its constraints but those
declared ``enabled = false``, and its tasks declared ``enabled = true``; a machine whose
owner cannot be reached is left out); a state adds what its ``enter`` and ``during`` blocks enable and what any
state nested in it may enable, removes what they disable, and hands what its ``exit``
leaves to the states its clauses lead to. A parallel state's regions also see what their
sibling regions may enable.
"""

from __future__ import annotations

import networkx as nx

from ..lang import ast
from ..lang.catalogue import SWITCH_WORDS
from .context import CheckContext


def _apply(blocks, enabled: frozenset[str]) -> frozenset[str]:
    result = set(enabled)
    for block in blocks:
        for action in block.actions if block else ():
            if isinstance(action, ast.Enable):
                result.update(n.text for n in action.names)
            elif isinstance(action, ast.Disable):
                result.difference_update(n.text for n in action.names)
    return frozenset(result)


def enabled_from_start(mission: ast.Mission) -> frozenset[str]:
    """The tasks and constraints active when the mission starts: constraints unless
    declared ``enabled = false``, tasks declared ``enabled = true``."""
    found = set()
    for decls, default in ((mission.constraints, True), (mission.tasks, False)):
        for decl in decls:
            value = next((p.value for p in decl.parameters if p.name.text == "enabled"),
                         None)
            switch = value.name.text if isinstance(value, ast.Reference) else None
            if (switch == "true") if switch in SWITCH_WORDS else default:
                found.add(decl.name.text)
    return frozenset(found)


def enabled_within(state: ast.StateDecl, memo: dict | None = None) -> frozenset[str]:
    """Everything the states nested in ``state`` enable somewhere, at any depth
    (``memo`` keeps the answers by state, for a walk over many states)."""
    memo = {} if memo is None else memo
    if id(state) in memo:
        return memo[id(state)]
    found = set()
    for region in state.regions:
        for inner in region.machine.states if region.machine is not None else ():
            found |= _apply(inner.blocks, frozenset())
            for transition in inner.transitions:
                found |= {n.text for a in transition.actions if isinstance(a, ast.Enable)
                          for n in a.names}
            found |= enabled_within(inner, memo)
    memo[id(state)] = frozenset(found)
    return memo[id(state)]


def may_be_enabled(ctx: CheckContext, graph: nx.DiGraph, decls: dict) -> dict[str, frozenset]:
    """Per state path: what may be enabled while its clauses are checked."""
    inside: dict[str, frozenset[str]] = {}
    memo: dict = {}
    for info in graph.graph["machines"].values():
        if info.start is None:
            continue
        if info.owner is None:
            initial = enabled_from_start(ctx.expanded)
        elif info.owner not in inside:
            continue
        else:
            initial = inside.get(info.owner, frozenset())
            owner = decls[info.owner]
            if owner.parallel:
                initial |= enabled_within(owner, memo)
        _machine(graph, info, decls, initial, inside, memo)
    return inside


def _machine(graph: nx.DiGraph, info, decls: dict, initial: frozenset, inside: dict,
             memo: dict) -> None:
    states = frozenset(info.states)
    arriving: dict[str, frozenset[str]] = {p: frozenset() for p in info.states}
    arriving[info.start] = initial
    pending, queued = [info.start], {info.start}
    while pending:
        path = pending.pop()
        queued.discard(path)
        state = decls[path]
        blocks: dict[str, ast.ActionBlock] = {}
        for block in state.blocks:
            blocks.setdefault(block.kind, block)
        inside[path] = _apply((blocks.get("enter"), blocks.get("during")),
                              arriving[path]) | enabled_within(state, memo)
        leaving = _apply((blocks.get("exit"),), inside[path])
        for successor in graph.successors(path):
            if successor not in states:
                continue
            merged = arriving[successor] | leaving
            if merged != arriving[successor] or successor not in inside:
                arriving[successor] = merged
                if successor not in queued:
                    queued.add(successor)
                    pending.append(successor)
