"""The state machines as one ``networkx.DiGraph`` with a containment tree.

Nodes are state paths (``approach``, ``carry/up``, ``both/left/above``: a parallel
state's region adds its name) with ``name`` (local to its machine), ``machine`` (the
path of the machine it belongs to: ``""`` for the mission's), ``final`` (bool),
``outcome`` (``"success"``/``"failure"`` for the mission's final states, ``"outcome"``
for a nested machine's finals, else ``None``), ``start`` (whether its machine starts
in it), ``kind`` (``simple``, ``compound``, ``parallel`` or ``final``) and ``span``.

An edge ``a -> b`` joins two states of one machine when some clause of ``a`` (its own
``when`` clauses, then its machine's top-level guards) leads to ``b``; it carries
``condition`` (the text of its clauses joined with ``or``), ``span`` (the first
clause's) and ``clauses`` (every :class:`Clause`, in the order they are checked). Final
states have no outgoing edges.

The graph's own attributes: ``start`` (the mission's start path or ``None``), ``guards``
(the mission's top-level clauses) and ``machines``: every :class:`MachineInfo` by path,
parents first (the containment tree: a machine's ``owner`` is the state it belongs to).
"""

from __future__ import annotations

from dataclasses import dataclass

import networkx as nx

from ..diagnostics import Span
from ..lang import ast
from ..lang.formatter import format_condition


@dataclass(frozen=True)
class Clause:
    """One ``when`` clause on an edge: its condition as text, where it is written, whether
    it is a top-level guard and its rank among the state's clauses (0 is checked first)."""

    condition: str
    span: Span
    guard: bool
    order: int


@dataclass(frozen=True)
class Guard:
    """A machine's top-level ``when`` clause: checked in every non-final state of the
    machine after its own."""

    condition: str
    target: str
    span: Span


@dataclass(frozen=True)
class MachineInfo:
    """One machine of the containment tree. ``owner`` is the path of the state it
    belongs to (``None`` for the mission's), ``region`` its name in a parallel state,
    ``start`` the path of its start state (``None`` when it has no state), ``states``
    its states' paths in declaration order, ``guards`` its top-level clauses (targets
    as paths)."""

    path: str
    owner: str | None
    region: str | None
    start: str | None
    states: tuple[str, ...]
    guards: tuple[Guard, ...]


def join(path: str, name: str) -> str:
    """The path of ``name`` inside the machine at ``path``."""
    return f"{path}/{name}" if path else name


def machine_start(machine: ast.Machine) -> str | None:
    """The local name of the state a machine starts in: ``start`` when it names one of
    its states, else its first state."""
    names = [s.name.text for s in machine.states]
    if machine.start is not None:
        return machine.start.state.text if machine.start.state.text in names else None
    return names[0] if names else None


def region_machine(region: ast.Region) -> ast.Machine:
    """A region's machine (an instance region's bound machine; empty when unbound)."""
    return region.machine if region.machine is not None else ast.Machine()


def build_state_graph(mission: ast.Mission) -> nx.DiGraph:
    """The graph of ``mission``'s machines (an expanded tree: behaviour instances bound);
    clauses to unknown states are left out, a repeated state name keeps the first."""
    graph = nx.DiGraph(start=None, guards=(), machines={})
    _add_machine(graph, mission.machine, "", None, None, {}, root=True)
    root = graph.graph["machines"][""]
    graph.graph["start"] = root.start
    graph.graph["guards"] = root.guards
    return graph


@dataclass(frozen=True)
class _Shape:
    """What a machine puts in the graph wherever it is, by local names: its states (the
    first of each name), its start, its top-level clauses that lead to one of its
    states (with their text) and its edges' clauses, edges in the order first met."""

    states: dict[str, ast.StateDecl]
    start: str | None
    guards: tuple[tuple[str, ast.Transition], ...]
    edges: dict[tuple[str, str], tuple[Clause, ...]]


def _shape(machine: ast.Machine) -> _Shape:
    states: dict[str, ast.StateDecl] = {}
    for state in machine.states:
        states.setdefault(state.name.text, state)
    machine_guards = [(g, True, format_condition(g.condition) if g.target.text in states
                       else None) for g in machine.guards]
    edges: dict[tuple[str, str], tuple[Clause, ...]] = {}
    for name, state in states.items():
        if state.final:
            continue
        ordered = [(t, False, None) for t in state.transitions] + machine_guards
        for order, (transition, guard, text) in enumerate(ordered):
            target = transition.target.text
            if target not in states:
                continue
            clause = Clause(format_condition(transition.condition) if text is None else text,
                            transition.span, guard, order)
            edges[name, target] = edges.get((name, target), ()) + (clause,)
    guards = tuple((text, g) for g, _, text in machine_guards if text is not None)
    return _Shape(states, machine_start(machine), guards, edges)


def _add_machine(graph: nx.DiGraph, machine: ast.Machine, path: str, owner: str | None,
                 region: str | None, shapes: dict, root: bool = False) -> None:
    """Add ``machine`` at ``path`` and the machines in its states; ``shapes`` keeps each
    machine's :class:`_Shape` (with the machine, by its identity): an expanded tree
    shares one machine between the instances that bind the same values."""
    known = shapes.get(id(machine))
    if known is None:
        known = shapes[id(machine)] = (machine, _shape(machine))
    shape = known[1]
    states, start = shape.states, shape.start
    graph.graph["machines"][path] = MachineInfo(
        path, owner, region, join(path, start) if start in states else None,
        tuple(join(path, n) for n in states),
        tuple(Guard(text, join(path, g.target.text), g.span) for text, g in shape.guards))
    for name, state in states.items():
        state_path = join(path, name)
        graph.add_node(state_path, name=name, machine=path, final=state.final,
                       outcome=_outcome(state, root), start=name == start,
                       kind=_kind(state), span=state.name.span)
        for inner in state.regions:
            inner_path = join(state_path, inner.name.text) if inner.name else state_path
            _add_machine(graph, region_machine(inner), inner_path, state_path,
                         inner.name.text if inner.name else None, shapes)
    for (source, target), clauses in shape.edges.items():
        _add_clauses(graph, join(path, source), join(path, target), clauses)


def _outcome(state: ast.StateDecl, root: bool) -> str | None:
    if not state.final:
        return None
    if not root:
        return "outcome"
    return state.outcome.text if state.outcome else "success"


def _kind(state: ast.StateDecl) -> str:
    if state.final:
        return "final"
    if state.parallel:
        return "parallel"
    return "compound" if state.regions else "simple"


def _add_clauses(graph: nx.DiGraph, source: str, target: str,
                 clauses: tuple[Clause, ...]) -> None:
    if graph.has_edge(source, target):
        data = graph.edges[source, target]
        data["clauses"] = data["clauses"] + clauses
        data["condition"] = _condition(data["clauses"])
        return
    graph.add_edge(source, target, condition=_condition(clauses), span=clauses[0].span,
                   clauses=clauses)


def _condition(clauses: tuple[Clause, ...]) -> str:
    """The text of an edge's clauses: each in parentheses, joined with ``or``."""
    if len(clauses) == 1:
        return clauses[0].condition
    return " or ".join(f"({c.condition})" for c in clauses)


def own_clauses(graph: nx.DiGraph, source: str, target: str) -> tuple[Clause, ...]:
    """The clauses of ``source -> target`` written in the state, not the guards."""
    return tuple(c for c in graph.edges[source, target]["clauses"] if not c.guard)


def reached(graph: nx.DiGraph, states: frozenset[str], source: str,
            backwards: bool = False) -> set[str]:
    """``source`` and the ``states`` (those of its machine) that clauses lead to from
    ``source``, at any distance, through ``states`` (``backwards``: that lead to it)."""
    adjacent = graph.pred if backwards else graph.succ
    edges = nx.generic_bfs_edges(graph, source, lambda path: (
        other for other in adjacent[path] if other in states))
    return {source, *(other for _, other in edges)}
