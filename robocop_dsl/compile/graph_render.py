"""Draw a state graph as Graphviz dot or Mermaid text.

States are boxes; the start state has an arrow from a start dot, final states are
double circles (red when the outcome is failure). Each transition is labelled with its
condition; the top-level guards are drawn once, from an "any state" node.
"""

from __future__ import annotations

import networkx as nx

from .state_graph import own_clauses

ANY_STATE = "any state"


def _label(graph: nx.DiGraph, source: str, target: str) -> str | None:
    clauses = own_clauses(graph, source, target)
    if not clauses:
        return None
    if len(clauses) == 1:
        return clauses[0].condition
    return " or ".join(f"({c.condition})" for c in clauses)


def _quote(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def to_dot(graph: nx.DiGraph, name: str = "mission") -> str:
    """Graphviz ``digraph`` text of the state graph."""
    lines = [f"digraph {_quote(name)} {{", "    rankdir=LR;",
             '    node [shape=box, style=rounded, fontname="Helvetica"];',
             '    edge [fontname="Helvetica", fontsize=10];']
    start = graph.graph.get("start")
    if start is not None:
        lines += ['    "__start" [shape=point, width=0.15, label=""];',
                  f'    "__start" -> {_quote(start)};']
    for state, data in graph.nodes(data=True):
        if data["final"]:
            color = ", color=red" if data["outcome"] == "failure" else ""
            lines.append(f"    {_quote(state)} [shape=doublecircle{color}];")
        else:
            lines.append(f"    {_quote(state)};")
    for source, target in graph.edges:
        label = _label(graph, source, target)
        if label is not None:
            lines.append(f"    {_quote(source)} -> {_quote(target)} [label={_quote(label)}];")
    guards = graph.graph.get("guards", ())
    if guards:
        lines.append(f'    "__any" [label={_quote(ANY_STATE)}, shape=plaintext];')
        for guard in guards:
            if guard.target in graph:
                lines.append(f'    "__any" -> {_quote(guard.target)} '
                             f'[label={_quote(guard.condition)}, style=dashed];')
    lines.append("}")
    return "\n".join(lines) + "\n"


def _mermaid_text(text: str) -> str:
    return (text.replace("#", "#35;").replace(":", "#58;").replace("<", "#lt;")
            .replace(">", "#gt;").replace('"', "#quot;"))


def to_mermaid(graph: nx.DiGraph) -> str:
    """Mermaid ``stateDiagram-v2`` text of the state graph."""
    lines = ["stateDiagram-v2"]
    start = graph.graph.get("start")
    if start is not None:
        lines.append(f"    [*] --> {start}")
    for source, target in graph.edges:
        label = _label(graph, source, target)
        if label is not None:
            lines.append(f"    {source} --> {target} : {_mermaid_text(label)}")
    guards = graph.graph.get("guards", ())
    if guards:
        lines.append(f"    state \"{ANY_STATE}\" as __any")
        for guard in guards:
            if guard.target in graph:
                lines.append(f"    __any --> {guard.target} : {_mermaid_text(guard.condition)}")
    for state, data in graph.nodes(data=True):
        if data["final"]:
            lines.append(f"    {state} --> [*]")
            if data["outcome"] == "failure":
                lines.append(f"    class {state} failure")
    if any(d["final"] and d["outcome"] == "failure" for _, d in graph.nodes(data=True)):
        lines.append("    classDef failure fill:#f8d7da,stroke:#c00")
    return "\n".join(lines) + "\n"
