"""Checks on the state graph, machine by machine: reachability, ways out, outcomes the
parent never handles, shadowed clauses, enabled tasks.

Severities: a mission that can never finish (no final state reachable from the start, or
a reachable state with no clause at all, in the mission's own machine) is an error, and
so is a parallel state whose ``done`` is read but can never hold; dead code and probable
mistakes (an unreachable state, a state that can only loop, a nested machine with no
final, a final that no clause of the parent reads, a clause that never fires, a task
read before any state enables it) are warnings. A problem in a behaviour instance's
machine carries the notes naming the instances it is in.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import networkx as nx

from ..lang import ast
from .conditions import members_of, tasks_read
from .context import CheckContext
from .enabled import may_be_enabled
from .expand import instance_note

if TYPE_CHECKING:
    from ..compile.state_graph import MachineInfo

_NON_NEGATIVE = (ast.Elapsed, ast.Time, ast.Distance, ast.Member)
"""Measures that are never negative (a clearance, a `Distance` too, is negative when
shapes overlap)."""


def check_state_graph(ctx: CheckContext, mission: ast.Mission, graph: nx.DiGraph) -> None:
    """Run every graph check on ``graph`` (built from the expanded ``mission``)."""
    decls = declarations(ctx, mission.machine)
    for info in graph.graph["machines"].values():
        _check_machine(ctx, graph, info, decls)
    _check_shadowed(ctx, decls, mission.machine)
    if graph.graph["machines"].get(""):
        _check_enabled(ctx, graph, decls)
    ctx.notes = ()


def check_behavior_graph(ctx: CheckContext, name: ast.Name, machine: ast.Machine) -> None:
    """The graph checks of a behaviour's machine checked on its own: its machines'
    reachability and finals, the outcomes its nested states leave unread, shadowed
    clauses."""
    from ..compile.state_graph import build_state_graph

    wrapper = ast.StateDecl(name, regions=(ast.Region(None, machine=machine),),
                            span=name.span)
    root = ast.Machine((wrapper,))
    graph = build_state_graph(ast.Mission((wrapper,)))
    graph.graph["behavior"] = True
    decls = declarations(ctx, root)
    for info in graph.graph["machines"].values():
        if info.owner is not None:
            _check_machine(ctx, graph, info, decls, outcomes=info.owner != name.text)
    _check_shadowed(ctx, decls, root)
    ctx.notes = ()


def declarations(ctx: CheckContext, machine: ast.Machine, path: str = "",
                 notes: tuple[str, ...] = (), found: dict | None = None) -> dict:
    """Every state declaration by path (the graph's paths), every machine by
    ``("machine", path)``, its top-level clauses by ``("guards", path)`` and the notes
    naming the instances it is in by ``("notes", path)``."""
    found = {} if found is None else found
    found.setdefault(("machine", path), machine)
    found.setdefault(("guards", path), tuple(machine.guards))
    found.setdefault(("notes", path), notes)
    for state in machine.states:
        state_path = f"{path}/{state.name.text}" if path else state.name.text
        found.setdefault(state_path, state)
        for region in state.regions:
            inner = f"{state_path}/{region.name.text}" if region.name else state_path
            if region.machine is not None:
                own = (instance_note(ctx, region.instance),) if region.instance else ()
                declarations(ctx, region.machine, inner, own + notes, found)
    return found


def _located(ctx: CheckContext, decls: dict, machine_path: str) -> None:
    """Give the diagnostics that follow the notes of the machine at ``machine_path``."""
    ctx.notes = decls.get(("notes", machine_path), ())


def _machine_text(graph: nx.DiGraph, info: MachineInfo) -> str:
    owner = graph.nodes[info.owner]["name"]
    if info.region:
        return f"region '{info.region}' of '{owner}'"
    return f"the machine of '{owner}'" if graph.nodes[info.owner]["machine"] or \
        not graph.graph.get("behavior") else f"behavior '{owner}'"


def _check_machine(ctx: CheckContext, graph: nx.DiGraph, info: MachineInfo,
                   decls: dict, outcomes: bool = True) -> None:
    from ..compile.state_graph import reached

    start = info.start
    if start is None:
        return
    _located(ctx, decls, info.path)
    root = info.owner is None
    reachable = reached(graph, frozenset(info.states), start)
    for path in info.states:
        if path not in reachable:
            ctx.warning("unreachable-state", f"state '{graph.nodes[path]['name']}' cannot be "
                        f"reached from '{graph.nodes[start]['name']}'",
                        graph.nodes[path]["span"],
                        "no clause leads to it: remove it or add a 'when ... ->' to it")
    finals = {p for p in info.states if graph.nodes[p]["final"]}
    if not finals & reachable:
        report = ctx.error if root else ctx.warning
        where = "" if root else f" in {_machine_text(graph, info)}"
        report("no-final-reachable", f"no final state can be reached from "
               f"'{graph.nodes[start]['name']}'{where}", graph.nodes[start]["span"],
               ("the mission would never end: add a path to a 'final NAME' state" if root
                else "only its parent's clauses can leave it: add a final its parent reads")
               if finals else "declare one: final done")
    if root:
        _check_ways_out(ctx, graph, info, reachable, finals)
    elif outcomes:
        _check_outcomes(ctx, graph, info, decls, finals & reachable)
        _check_done(ctx, graph, info, decls, finals & reachable)


def _check_ways_out(ctx, graph: nx.DiGraph, info: MachineInfo, reachable: set,
                    finals: set) -> None:
    from ..compile.state_graph import reached

    states = frozenset(info.states)
    ending = set(finals)
    for final in finals:
        ending |= reached(graph, states, final, backwards=True)
    for path in sorted(reachable - finals, key=lambda p: graph.nodes[p]["span"].line):
        name, span = graph.nodes[path]["name"], graph.nodes[path]["span"]
        if not any(other in states for other in graph.succ[path]):
            ctx.error("dead-end-state", f"state '{name}' has no way out", span,
                      "add a 'when CONDITION -> STATE' clause or make it 'final'")
        elif finals & reachable and path not in ending:
            ctx.warning("no-way-to-final", f"from state '{name}' no final state can be "
                        "reached", span, "its clauses only lead to states that loop among "
                        "themselves")


def _parent_reads(graph: nx.DiGraph, info: MachineInfo, decls: dict) -> list[ast.Member]:
    """The members of the owner state's own clauses and its machine's guards that read
    the owner (``S.F``, ``S.R.F``, ``S.done``)."""
    owner = decls[info.owner]
    guards = decls[("guards", graph.nodes[info.owner]["machine"])]
    members = []
    for transition in (*owner.transitions, *guards):
        members += [m for m in members_of(transition.condition)
                    if m.owner.text == owner.name.text]
    return members


def _check_outcomes(ctx, graph: nx.DiGraph, info: MachineInfo, decls: dict,
                    finals: set) -> None:
    reads = _parent_reads(graph, info, decls)
    owner = graph.nodes[info.owner]["name"]
    for path in sorted(finals, key=lambda p: graph.nodes[p]["span"].line):
        name = graph.nodes[path]["name"]
        handled = any((m.field.text == name and _region_of(m) == info.region)
                      or (info.region is not None and m.field.text == "done")
                      for m in reads)
        if not handled:
            read = f"{owner}.{info.region}.{name}" if info.region else f"{owner}.{name}"
            ctx.warning("unhandled-outcome", f"no clause of '{owner}' reads its outcome "
                        f"'{name}': the machine would stay there", graph.nodes[path]["span"],
                        f"add to '{owner}': when {read} -> NEXT")


def _region_of(member: ast.Member) -> str | None:
    return member.region.text if member.region else None


def _check_done(ctx, graph: nx.DiGraph, info: MachineInfo, decls: dict, finals: set) -> None:
    if info.region is None or finals:
        return
    owner = graph.nodes[info.owner]["name"]
    _located(ctx, decls, graph.nodes[info.owner]["machine"])
    for member in _parent_reads(graph, info, decls):
        if member.field.text == "done" and member.region is None:
            ctx.error("done-never-holds", f"'{owner}.done' can never hold: region "
                      f"'{info.region}' cannot reach a final state", member.span,
                      f"add a final to region '{info.region}' and a way to it")


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
    if isinstance(condition, ast.Comparison) and isinstance(condition.measure, _NON_NEGATIVE) \
            and not isinstance(condition.measure, ast.Clearance) \
            and isinstance(condition.quantity, ast.Quantity):
        value, operator = condition.quantity.value, condition.operator
        if (operator == ">=" and value <= 0) or (operator == ">" and value < 0):
            return True
        if (operator == "<" and value <= 0) or (operator == "<=" and value < 0):
            return False
    return None


def _check_shadowed(ctx: CheckContext, decls: dict, root: ast.Machine) -> None:
    for key, machine in decls.items():
        if not (isinstance(key, tuple) and key[0] == "machine"):
            continue
        _located(ctx, decls, key[1])
        guards = decls[("guards", key[1])]
        transitions = list(guards)
        for state in machine.states:
            if not state.final:
                _report_after_always(ctx, state.transitions, f"in state '{state.name.text}'")
                transitions += state.transitions
        _report_after_always(ctx, guards, "among the top-level clauses"
                             if machine is root else "among the machine's top-level clauses")
        for transition in transitions:
            if truth(transition.condition) is False:
                ctx.warning("shadowed-transition", "this clause never fires: its condition "
                            "is never true", transition.span)


def _report_after_always(ctx: CheckContext, transitions, where: str) -> None:
    transitions = tuple(transitions)
    always = next((t for t in transitions if truth(t.condition) is True), None)
    if always is None:
        return
    for transition in transitions[transitions.index(always) + 1:]:
        ctx.warning("shadowed-transition", f"this clause never fires {where}: the clause "
                    f"at {ctx.where(always.span)} is always true and is checked first",
                    transition.span, "move it before the always-true clause or remove it")


# ---- tasks read before they are enabled ------------------------------------------

def _check_enabled(ctx: CheckContext, graph: nx.DiGraph, decls: dict) -> None:
    inside = may_be_enabled(ctx, graph, decls)
    for path in sorted(inside, key=lambda p: graph.nodes[p]["span"].line):
        state = decls[path]
        _located(ctx, decls, graph.nodes[path]["machine"])
        for transition in state.transitions:
            for task in tasks_read(transition.condition):
                if task.text in ctx.symbols.tasks and task.text not in inside[path]:
                    ctx.warning("task-never-enabled", f"task '{task.text}' is read in state "
                                f"'{state.name.text}' but no path to it enables it",
                                task.span, f"add 'enable {task.text}' to an enter block on "
                                "the way")
    for info in graph.graph["machines"].values():
        guards = decls.get(("guards", info.path))
        if not guards:
            continue
        _located(ctx, decls, info.path)
        anywhere = frozenset().union(*(inside[p] for p in info.states if p in inside))
        for guard in guards:
            for task in tasks_read(guard.condition):
                if task.text in ctx.symbols.tasks and task.text not in anywhere:
                    ctx.warning("task-never-enabled", f"task '{task.text}' is read by a "
                                "top-level clause but no state enables it", task.span,
                                f"add 'enable {task.text}' to an enter block")
