"""Checks on the state graph: reachability, ways out, shadowed clauses, enabled tasks.

Severities: a mission that can never finish (no final state reachable from the start, or
a reachable state with no clause at all) is an error; dead code and probable mistakes
(an unreachable state, a state that can only loop, a clause that never fires, a task read
before any state enables it) are warnings.
"""

from __future__ import annotations

import networkx as nx

from ..lang import ast
from .conditions import tasks_read
from .context import CheckContext

_NON_NEGATIVE = (ast.Elapsed, ast.Time, ast.Distance, ast.Member)


def check_state_graph(ctx: CheckContext, mission: ast.Mission, graph: nx.DiGraph) -> None:
    """Run every graph check on ``graph`` (built from ``mission``)."""
    start = graph.graph.get("start")
    if start is None or start not in graph:
        return
    reachable = nx.descendants(graph, start) | {start}
    states = ctx.symbols.states
    for name in graph.nodes:
        if name not in reachable:
            ctx.warning("unreachable-state", f"state '{name}' cannot be reached from "
                        f"'{start}'", states[name].name.span,
                        "no clause leads to it: remove it or add a 'when ... ->' to it")
    finals = {n for n in graph.nodes if graph.nodes[n]["final"]}
    if not finals & reachable:
        ctx.error("no-final-reachable", f"no final state can be reached from '{start}'",
                  states[start].name.span, "the mission would never end: add a path to a "
                  "'final NAME' state" if finals else "declare one: final done")
    ending = set(finals)
    for final in finals:
        ending |= nx.ancestors(graph, final)
    for name in sorted(reachable - finals, key=lambda n: states[n].span.line):
        if graph.out_degree(name) == 0:
            ctx.error("dead-end-state", f"state '{name}' has no way out",
                      states[name].name.span,
                      "add a 'when CONDITION -> STATE' clause or make it 'final'")
        elif finals & reachable and name not in ending:
            ctx.warning("no-way-to-final", f"from state '{name}' no final state can be "
                        "reached", states[name].name.span,
                        "its clauses only lead to states that loop among themselves")
    _check_shadowed(ctx, mission)
    _check_enabled(ctx, mission, graph, reachable)


# ---- clauses that can never fire -----------------------------------------------

def truth(condition: ast.Condition) -> bool | None:
    """``True``/``False`` when ``condition`` is so in every cycle, else ``None``."""
    if isinstance(condition, ast.Not):
        inner = truth(condition.operand)
        return None if inner is None else not inner
    if isinstance(condition, (ast.And, ast.Or)):
        values = [truth(c) for c in condition.operands]
        decisive = isinstance(condition, ast.Or)
        if decisive in values:
            return decisive
        return (not decisive) if all(v is not None for v in values) else None
    if isinstance(condition, ast.Comparison) and isinstance(condition.measure, _NON_NEGATIVE):
        value, operator = condition.quantity.value, condition.operator
        if (operator == ">=" and value <= 0) or (operator == ">" and value < 0):
            return True
        if (operator == "<" and value <= 0) or (operator == "<=" and value < 0):
            return False
    return None


def _check_shadowed(ctx: CheckContext, mission: ast.Mission) -> None:
    for state in ctx.symbols.states.values():
        if not state.final:
            _report_after_always(ctx, state.transitions,
                                 f"in state '{state.name.text}'")
    _report_after_always(ctx, tuple(mission.guards), "among the top-level clauses")
    for transition in [t for s in ctx.symbols.states.values() for t in s.transitions] \
            + list(mission.guards):
        if truth(transition.condition) is False:
            ctx.warning("shadowed-transition", "this clause never fires: its condition is "
                        "never true", transition.span)


def _report_after_always(ctx: CheckContext, transitions, where: str) -> None:
    always = next((t for t in transitions if truth(t.condition) is True), None)
    if always is None:
        return
    for transition in transitions[transitions.index(always) + 1:]:
        ctx.warning("shadowed-transition", f"this clause never fires {where}: the clause "
                    f"at line {always.span.line} is always true and is checked first",
                    transition.span, "move it before the always-true clause or remove it")


# ---- tasks read before they are enabled ------------------------------------------

def _apply(blocks, enabled: frozenset[str]) -> frozenset[str]:
    result = set(enabled)
    for block in blocks:
        for action in block.actions if block else ():
            if isinstance(action, ast.Enable):
                result.update(n.text for n in action.names)
            elif isinstance(action, ast.Disable):
                result.difference_update(n.text for n in action.names)
    return frozenset(result)


def may_be_enabled(ctx: CheckContext, graph: nx.DiGraph) -> dict[str, frozenset[str]]:
    """Per state: what may be enabled while its clauses are checked (on some path)."""
    states = ctx.symbols.states
    start = graph.graph["start"]
    arriving: dict[str, frozenset[str]] = {n: frozenset() for n in graph.nodes}
    arriving[start] = frozenset(ctx.symbols.constraints)
    inside: dict[str, frozenset[str]] = {}
    pending = [start]
    while pending:
        name = pending.pop()
        state = states[name]
        inside[name] = _apply((state.block("enter"), state.block("during")), arriving[name])
        leaving = _apply((state.block("exit"),), inside[name])
        for successor in graph.successors(name):
            merged = arriving[successor] | leaving
            if merged != arriving[successor] or successor not in inside:
                arriving[successor] = merged
                pending.append(successor)
    return inside


def _check_enabled(ctx: CheckContext, mission: ast.Mission, graph: nx.DiGraph,
                   reachable: set[str]) -> None:
    inside = may_be_enabled(ctx, graph)
    for name in sorted(reachable, key=lambda n: ctx.symbols.states[n].span.line):
        for transition in ctx.symbols.states[name].transitions:
            for task in tasks_read(transition.condition):
                if task.text in ctx.symbols.tasks and task.text not in inside[name]:
                    ctx.warning("task-never-enabled", f"task '{task.text}' is read in state "
                                f"'{name}' but no path to it enables it", task.span,
                                f"add 'enable {task.text}' to an enter block on the way")
    anywhere = frozenset().union(*(inside[n] for n in reachable if n in inside))
    for guard in mission.guards:
        for task in tasks_read(guard.condition):
            if task.text in ctx.symbols.tasks and task.text not in anywhere:
                ctx.warning("task-never-enabled", f"task '{task.text}' is read by a top-level "
                            "clause but no state enables it", task.span,
                            f"add 'enable {task.text}' to an enter block")
