"""The state machine as a ``networkx.DiGraph``.

Nodes are state names with ``final`` (bool), ``outcome`` (``"success"``/``"failure"``
for final states, else ``None``), ``start`` (bool) and ``span``. An edge ``a -> b``
exists when some clause of ``a`` (its own ``when`` clauses, then the top-level guards)
leads to ``b``; it carries ``condition`` (the text of its clauses joined with ``or``),
``span`` (the first clause's) and ``clauses`` (every :class:`Clause`, in the order they
are checked). Final states have no outgoing edges. The graph's own attributes are
``start`` (a state name or ``None``) and ``guards`` (the top-level clauses).
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
    """A top-level ``when`` clause: checked in every non-final state after its own."""

    condition: str
    target: str
    span: Span


def build_state_graph(mission: ast.Mission, start: str | None) -> nx.DiGraph:
    """The graph of ``mission``'s states; clauses to unknown states are left out."""
    graph = nx.DiGraph(start=start, guards=tuple(
        Guard(format_condition(g.condition), g.target.text, g.span) for g in mission.guards))
    states: dict[str, ast.StateDecl] = {}
    for state in mission.states:
        if state.name.text in states:
            continue
        states[state.name.text] = state
        outcome = (state.outcome.text if state.outcome else "success") if state.final else None
        graph.add_node(state.name.text, final=state.final, outcome=outcome,
                       start=state.name.text == start, span=state.name.span)
    for name, state in states.items():
        if state.final:
            continue
        ordered = [(t, False) for t in state.transitions] + [(g, True) for g in mission.guards]
        for order, (transition, guard) in enumerate(ordered):
            if transition.target.text not in states:
                continue
            clause = Clause(format_condition(transition.condition), transition.span, guard,
                            order)
            _add_clause(graph, name, transition.target.text, clause)
    return graph


def _add_clause(graph: nx.DiGraph, source: str, target: str, clause: Clause) -> None:
    if graph.has_edge(source, target):
        data = graph.edges[source, target]
        data["clauses"] = data["clauses"] + (clause,)
        data["condition"] = " or ".join(f"({c.condition})" for c in data["clauses"])
        return
    graph.add_edge(source, target, condition=clause.condition, span=clause.span,
                   clauses=(clause,))


def own_clauses(graph: nx.DiGraph, source: str, target: str) -> tuple[Clause, ...]:
    """The clauses of ``source -> target`` written in the state, not the guards."""
    return tuple(c for c in graph.edges[source, target]["clauses"] if not c.guard)
