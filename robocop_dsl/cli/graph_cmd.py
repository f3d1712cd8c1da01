"""``robocop-mission graph FILE``: print a mission's state graph as dot or Mermaid.

Exit codes: 0 printed, 1 the mission has errors (printed on stderr), 2 usage error.
"""

from __future__ import annotations

import sys

from ..sources import not_a_file


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "graph", help="print a mission's state graph (Graphviz dot or Mermaid)",
        description="Check a mission and print its states and transitions: the start and "
                    "final states marked, transitions labelled with their condition, the "
                    "top-level 'when' clauses drawn once from 'any state'.")
    parser.add_argument("file", metavar="FILE", help=".mission file")
    parser.add_argument("--format", choices=("dot", "mermaid"), default="dot")
    parser.set_defaults(command=run)


def run(args) -> int:
    from ..compile import check_file, to_dot, to_mermaid

    problem = not_a_file(args.file)
    if problem:
        print(f"robocop-mission graph: error: {problem}: {args.file}", file=sys.stderr)
        return 2
    result = check_file(args.file)
    for diagnostic in result.diagnostics:
        print(diagnostic.render(), file=sys.stderr)
    if result.mission is None:
        return 1
    if args.format == "mermaid":
        print(to_mermaid(result.mission.graph), end="")
    else:
        print(to_dot(result.mission.graph, result.mission.name), end="")
    return 0
