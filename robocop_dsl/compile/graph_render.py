"""Draw a state graph as Graphviz dot or Mermaid text.

States are boxes; each machine's start state has an arrow from a start dot, final
states are double circles (red when the mission's outcome is failure). A compound
state holds its machine: a cluster in dot, a composite state in Mermaid; a parallel
state holds one machine per region (dashed clusters, ``--`` between regions). Each
transition is labelled with the state's own condition; a machine's top-level guards
are drawn once, from an "any state" node inside that machine.
"""

from __future__ import annotations

from collections.abc import Iterator

import networkx as nx

from .state_graph import MachineInfo, own_clauses

ANY_STATE = "any state"
INDENT = "    "
NESTED = ("compound", "parallel")
FONT = 'fontname="Helvetica"'


def _label(graph: nx.DiGraph, source: str, target: str) -> str | None:
    clauses = own_clauses(graph, source, target)
    if not clauses:
        return None
    if len(clauses) == 1:
        return clauses[0].condition
    return " or ".join(f"({c.condition})" for c in clauses)


def _root(graph: nx.DiGraph) -> MachineInfo:
    return graph.graph["machines"][""]


def _inner(graph: nx.DiGraph, state: str) -> list[MachineInfo]:
    """The machines a compound or parallel state holds, regions in declaration order."""
    return [m for m in graph.graph["machines"].values() if m.owner == state]


def _transitions(graph: nx.DiGraph, info: MachineInfo) -> Iterator[tuple[str, str, str]]:
    """``(source, target, label)`` of a machine's edges that have clauses of their own."""
    for source, target in graph.out_edges(info.states):
        label = _label(graph, source, target)
        if label is not None:
            yield source, target, label


def _is_failure(data: dict) -> bool:
    return data["final"] and data["outcome"] == "failure"


def _nested(graph: nx.DiGraph, state: str) -> bool:
    return graph.nodes[state]["kind"] in NESTED


def _aux(prefix: str, path: str) -> str:
    """The id of a machine's start or "any state" node."""
    return f"{prefix}/{path}" if path else prefix


# Graphviz dot

def _quote(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _attrs(pairs: list[str]) -> str:
    return f" [{', '.join(pairs)}]" if pairs else ""


def _cluster(state: str) -> str:
    return _quote(f"cluster_{state}")


def _ends(graph: nx.DiGraph, source: str | None, target: str) -> list[str]:
    """``ltail``/``lhead`` so that an edge leaving or entering a cluster meets its border."""
    if source == target:
        return []
    pairs = []
    if source is not None and _nested(graph, source):
        pairs.append(f"ltail={_cluster(source)}")
    if _nested(graph, target):
        pairs.append(f"lhead={_cluster(target)}")
    return pairs


def to_dot(graph: nx.DiGraph, name: str = "mission") -> str:
    """Graphviz ``digraph`` text of the state graph."""
    lines = [f"digraph {_quote(name)} {{", f"{INDENT}rankdir=LR;"]
    if len(graph.graph["machines"]) > 1:
        lines.append(f"{INDENT}compound=true;")
    lines += [f"{INDENT}node [shape=box, style=rounded, {FONT}];",
              f"{INDENT}edge [{FONT}, fontsize=10];"]
    lines += _dot_machine(graph, _root(graph), 1)
    lines.append("}")
    return "\n".join(lines) + "\n"


def _dot_machine(graph: nx.DiGraph, info: MachineInfo, depth: int) -> list[str]:
    pad = INDENT * depth
    lines = []
    if info.start is not None:
        start = _quote(_aux("__start", info.path))
        lines += [f'{pad}{start} [shape=point, width=0.15, label=""];',
                  f"{pad}{start} -> {_quote(info.start)}"
                  f"{_attrs(_ends(graph, None, info.start))};"]
    for state in info.states:
        lines += _dot_state(graph, state, depth)
    for source, target, label in _transitions(graph, info):
        pairs = [f"label={_quote(label)}", *_ends(graph, source, target)]
        lines.append(f"{pad}{_quote(source)} -> {_quote(target)}{_attrs(pairs)};")
    if info.guards:
        any_state = _quote(_aux("__any", info.path))
        lines.append(f"{pad}{any_state} [label={_quote(ANY_STATE)}, shape=plaintext];")
        for guard in info.guards:
            pairs = [f"label={_quote(guard.condition)}", "style=dashed",
                     *_ends(graph, None, guard.target)]
            lines.append(f"{pad}{any_state} -> {_quote(guard.target)}{_attrs(pairs)};")
    return lines


def _dot_state(graph: nx.DiGraph, state: str, depth: int) -> list[str]:
    if _nested(graph, state):
        return _dot_cluster(graph, state, depth)
    data = graph.nodes[state]
    pairs = [] if data["name"] == state else [f"label={_quote(data['name'])}"]
    if data["final"]:
        pairs.append("shape=doublecircle")
    if _is_failure(data):
        pairs.append("color=red")
    return [f"{INDENT * depth}{_quote(state)}{_attrs(pairs)};"]


def _dot_cluster(graph: nx.DiGraph, state: str, depth: int) -> list[str]:
    """A compound or parallel state: a cluster with an invisible anchor for its edges."""
    pad, inner = INDENT * depth, INDENT * (depth + 1)
    lines = [f"{pad}subgraph {_cluster(state)} {{",
             f"{inner}label={_quote(graph.nodes[state]['name'])}; style=rounded; {FONT};",
             f'{inner}{_quote(state)} [shape=point, style=invis, label=""];']
    for info in _inner(graph, state):
        if info.region is None:
            lines += _dot_machine(graph, info, depth + 1)
        else:
            lines += [f"{inner}subgraph {_cluster(info.path)} {{",
                      f"{inner}{INDENT}label={_quote(info.region)}; style=dashed; {FONT};",
                      *_dot_machine(graph, info, depth + 2),
                      f"{inner}}}"]
    lines.append(f"{pad}}}")
    return lines


# Mermaid

def _mermaid_text(text: str) -> str:
    return (text.replace("#", "#35;").replace(":", "#58;").replace("<", "#lt;")
            .replace(">", "#gt;").replace('"', "#quot;"))


def _mermaid_ids(graph: nx.DiGraph) -> dict[str, str]:
    """A unique Mermaid id per state, from its path (``both/left/above`` is
    ``both_left_above``) and unlike the ids Mermaid gives the start and end of the
    diagram and of each composite state (``carry_start``, ``carry_end``); shallower
    states are served first, so the mission's keep their names."""
    ids: dict[str, str] = {}
    used = {"root_start", "root_end"}
    for state in sorted(graph, key=lambda path: path.count("/")):
        ends = ("", "_start", "_end") if _nested(graph, state) else ("",)
        base = candidate = state.replace("/", "_")
        suffix = 2
        while any(candidate + end in used for end in ends):
            candidate, suffix = f"{base}_{suffix}", suffix + 1
        used.update(candidate + end for end in ends)
        ids[state] = candidate
    return ids


def to_mermaid(graph: nx.DiGraph) -> str:
    """Mermaid ``stateDiagram-v2`` text of the state graph."""
    lines = ["stateDiagram-v2", *_mermaid_machine(graph, _root(graph),
                                                  _mermaid_ids(graph), 1)]
    if any(_is_failure(data) for _, data in graph.nodes(data=True)):
        lines.append(f"{INDENT}classDef failure fill:#f8d7da,stroke:#c00")
    return "\n".join(lines) + "\n"


def _mermaid_machine(graph: nx.DiGraph, info: MachineInfo, ids: dict[str, str],
                     depth: int) -> list[str]:
    pad = INDENT * depth
    lines = [f"{pad}[*] --> {ids[info.start]}"] if info.start is not None else []
    for state in info.states:
        lines += _mermaid_state(graph, state, ids, depth)
    for source, target, label in _transitions(graph, info):
        lines.append(f"{pad}{ids[source]} --> {ids[target]} : {_mermaid_text(label)}")
    if info.guards:
        any_state = _aux("__any", info.path).replace("/", "_")
        lines.append(f'{pad}state "{ANY_STATE}" as {any_state}')
        for guard in info.guards:
            lines.append(f"{pad}{any_state} --> {ids[guard.target]} : "
                         f"{_mermaid_text(guard.condition)}")
    for state in info.states:
        data = graph.nodes[state]
        if data["final"]:
            lines.append(f"{pad}{ids[state]} --> [*]")
        if _is_failure(data):
            lines.append(f"{pad}class {ids[state]} failure")
    return lines


def _mermaid_state(graph: nx.DiGraph, state: str, ids: dict[str, str],
                   depth: int) -> list[str]:
    """A state's label when its id differs from its name; a composite block when it
    holds machines, regions separated by ``--``."""
    pad, name = INDENT * depth, graph.nodes[state]["name"]
    lines = [f'{pad}state "{name}" as {ids[state]}'] if ids[state] != name else []
    if not _nested(graph, state):
        return lines
    lines.append(f"{pad}state {ids[state]} {{")
    for index, info in enumerate(_inner(graph, state)):
        if index:
            lines.append(f"{pad}{INDENT}--")
        lines += _mermaid_machine(graph, info, ids, depth + 1)
    lines.append(f"{pad}}}")
    return lines
