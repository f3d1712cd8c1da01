"""``robocop-mission graph``: the state graph as dot or Mermaid."""

import argparse
from pathlib import Path

from robocop_dsl.cli import graph_cmd

REPO = Path(__file__).resolve().parent.parent


def graph(*argv: str) -> int:
    parser = argparse.ArgumentParser(prog="robocop-mission")
    graph_cmd.add_parser(parser.add_subparsers(dest="name", required=True))
    try:
        args = parser.parse_args(["graph", *argv])
    except SystemExit as exit_:
        return exit_.code
    return args.command(args)


def test_dot_by_default(capsys):
    """Graphviz dot: start arrow, double circles for finals, labelled edges."""
    assert graph(str(REPO / "missions" / "dual_arm.mission")) == 0
    out = capsys.readouterr().out
    assert out.startswith('digraph "dual_arm" {\n    rankdir=LR;\n')
    assert '    "__start" -> "initial_pose";\n' in out
    assert '    "done" [shape=doublecircle];\n' in out
    assert '    "rest" -> "done" [label="elapsed >= 1 s"];\n' in out
    assert '    "__any" -> "failed" [label="controller.failed", style=dashed];\n' in out
    assert out.endswith("}\n")


def test_mermaid(capsys):
    """Mermaid state diagram with the top-level guard drawn once."""
    assert graph(str(REPO / "missions" / "panda_reach.mission"), "--format", "mermaid") == 0
    out = capsys.readouterr().out.splitlines()
    assert out[:3] == ["stateDiagram-v2", "    [*] --> home",
                       "    home --> above : posture.reached"]
    assert out.count("    __any --> failed : controller.failed") == 1
    assert "    class failed failure" in out


def test_mission_with_errors_exits_one(capsys):
    """No graph for a mission with errors: the diagnostics go to stderr."""
    path = REPO / "tests" / "fixtures" / "invalid" / "unknown_state.mission"
    assert graph(str(path)) == 1
    captured = capsys.readouterr()
    assert captured.out == ""
    assert "error[unknown-state]" in captured.err


def test_usage_errors_exit_two(capsys):
    """A missing file or an unknown format is a usage error."""
    assert graph("nowhere.mission") == 2
    assert graph(str(REPO / "missions" / "pickup.mission"), "--format", "png") == 2
