"""``robocop-mission graph``: the state graph as dot or Mermaid."""

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from robocop_dsl.cli.main import main

REPO = Path(__file__).resolve().parent.parent

LIBRARY = """\
library common "Tasks and a behaviour for the composite mission."
world "bazar/sophia.yaml"

task left_tool: body_pose(bazar_left_hankamp_tool_object_side) {
    reference    = world
    interpolator = otg(max_velocity = 0.2 m/s, max_acceleration = 0.5 m/s^2)
    feedback     = proportional(gain = 5)
}

task right_tool: body_pose(bazar_right_hankamp_tool_object_side) {
    reference    = world
    interpolator = otg(max_velocity = 0.2 m/s, max_acceleration = 0.5 m/s^2)
    feedback     = proportional(gain = 5)
}

behavior approach(tool: task, point: body, height: length = 10 cm) {
    start above
    state above {
        enter { tool.target = point offset [0, 0, height] }
        when tool.reached and tool.position_error < 2 mm -> down
    }
    state down {
        enter { tool.target = point }
        when tool.reached and tool.position_error < 1 mm -> arrived
    }
    when elapsed > 15 s -> missed
    final arrived
    final missed
}
"""

MISSION = """\
mission two_parts "Pick with the left tool, then approach with both."
world "bazar/sophia.yaml"
import "common.mission"

state pick: approach(left_tool, pickup_point) {
    enter { enable left_tool }
    when pick.arrived -> carry
    when pick.missed and pick.visits < 3 -> pick
    when pick.missed -> failed
}

state carry {
    state up {
        enter { left_tool.target = pickup_point offset [0, 0, 15] cm }
        when left_tool.reached -> end
    }
    final end
    when carry.end -> both
    when elapsed > 20 s -> failed
}

state both: parallel {
    enter { enable right_tool }
    region left: approach(left_tool, drop_point)
    region right: approach(right_tool, pickup_point, height = 5 cm)
    when both.done -> done
    when both.left.missed or both.right.missed -> failed
}

when controller.failed -> failed
final done
final failed: failure
"""


def graph(*argv: str) -> int:
    return main(["graph", *argv])


@pytest.fixture
def composite(tmp_path):
    """A mission with a behaviour instance, a compound state and a parallel state."""
    (tmp_path / "common.mission").write_text(LIBRARY)
    path = tmp_path / "two_parts.mission"
    path.write_text(MISSION)
    return path


def _draw(capsys, path, fmt: str) -> str:
    assert graph(str(path), "--format", fmt) == 0
    return capsys.readouterr().out


def _dot_tree(dot: str) -> tuple[dict, dict]:
    """Each cluster's parent, label and style; each node's innermost cluster."""
    clusters, nodes, stack = {}, {}, [None]
    for line in dot.splitlines()[1:]:
        opened = re.match(r'\s*subgraph "(cluster_[^"]*)" \{', line)
        if opened:
            clusters[opened[1]] = {"parent": stack[-1]}
            stack.append(opened[1])
        elif line.strip() == "}":
            stack.pop()
        elif re.match(r'\s*label=', line):
            clusters[stack[-1]].update(re.findall(r'(\w+)="?([^";]*)"?;', line))
        elif re.match(r'\s*"[^"]*"( \[|;)', line):
            nodes[re.match(r'\s*"([^"]*)"', line)[1]] = stack[-1]
    return clusters, nodes


def test_dot_by_default(capsys):
    """Graphviz dot: start arrow, double circles for finals, labelled edges."""
    assert graph(str(REPO / "missions" / "dual_arm.mission")) == 0
    out = capsys.readouterr().out
    assert out.startswith('digraph "dual_arm" {\n    rankdir=LR;\n')
    assert '    "__start" -> "initial_pose";\n' in out
    assert '    "done" [shape=doublecircle];\n' in out
    assert '    "rest" -> "done" [label="elapsed >= 1 s"];\n' in out
    assert '    "__any" -> "failed" [label="controller.failed", style=dashed];\n' in out
    assert "subgraph" not in out and "compound" not in out
    assert out.endswith("}\n")


def test_mermaid(capsys):
    """Mermaid state diagram with the top-level guard drawn once."""
    assert graph(str(REPO / "missions" / "panda_reach.mission"), "--format", "mermaid") == 0
    out = capsys.readouterr().out.splitlines()
    assert out[:3] == ["stateDiagram-v2", "    [*] --> home",
                       "    home --> above : posture.reached"]
    assert out.count("    __any --> failed : controller.failed") == 1
    assert "    class failed failure" in out


def test_dot_nests_machines_in_clusters(composite, capsys):
    """Compound and parallel states are clusters, a parallel state's regions dashed
    sub-clusters; every state sits in its machine's cluster."""
    out = _draw(capsys, composite, "dot")
    clusters, nodes = _dot_tree(out)
    assert clusters == {
        "cluster_pick": {"parent": None, "label": "pick", "style": "rounded",
                         "fontname": "Helvetica"},
        "cluster_carry": {"parent": None, "label": "carry", "style": "rounded",
                          "fontname": "Helvetica"},
        "cluster_both": {"parent": None, "label": "both", "style": "rounded",
                         "fontname": "Helvetica"},
        "cluster_both/left": {"parent": "cluster_both", "label": "left",
                              "style": "dashed", "fontname": "Helvetica"},
        "cluster_both/right": {"parent": "cluster_both", "label": "right",
                               "style": "dashed", "fontname": "Helvetica"},
    }
    assert nodes["pick/above"] == nodes["pick/missed"] == "cluster_pick"
    assert nodes["carry/end"] == "cluster_carry"
    assert nodes["both/left/down"] == "cluster_both/left"
    assert nodes["both/right/arrived"] == "cluster_both/right"
    assert nodes["done"] is None and nodes["failed"] is None
    assert nodes["__any"] is None and nodes["__any/both/left"] == "cluster_both/left"
    assert "    compound=true;\n" in out


def test_dot_starts_finals_and_edges(composite, capsys):
    """Each machine has its start point; edges meet the clusters they leave or enter;
    each machine's guards are drawn once, from its own "any state"."""
    out = _draw(capsys, composite, "dot")
    assert '    "__start" -> "pick" [lhead="cluster_pick"];\n' in out
    assert '        "__start/pick" -> "pick/above";\n' in out
    assert '            "__start/both/right" -> "both/right/above";\n' in out
    assert '        "pick/arrived" [label="arrived", shape=doublecircle];\n' in out
    assert '    "failed" [shape=doublecircle, color=red];\n' in out
    assert ('    "pick" -> "carry" [label="pick.arrived", ltail="cluster_pick", '
            'lhead="cluster_carry"];\n') in out
    assert '    "pick" -> "pick" [label="pick.missed and pick.visits < 3"];\n' in out
    assert '    "carry" -> "failed" [label="elapsed > 20 s", ltail="cluster_carry"];\n' in out
    assert out.count("controller.failed") == 1
    assert out.count('"__any/both/left" -> "both/left/missed" '
                     '[label="elapsed > 15 s", style=dashed];') == 1


@pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz is not installed")
def test_dot_renders_with_graphviz(composite, capsys):
    """Graphviz lays the hierarchical drawing out without a warning."""
    out = _draw(capsys, composite, "dot")
    done = subprocess.run(["dot", "-Tsvg"], input=out, capture_output=True, text=True,
                          check=False)
    assert done.returncode == 0
    assert done.stderr == ""


def _block(lines: list[str], opening: str) -> list[str]:
    """The lines inside a Mermaid composite block, its closing brace left out."""
    start = lines.index(opening)
    indent = opening[:len(opening) - len(opening.lstrip())]
    end = lines.index(f"{indent}}}", start)
    return lines[start + 1:end]


def test_mermaid_composite_states(composite, capsys):
    """Compound states are composite blocks with their own start and finals; a
    parallel state's regions are split by ``--``; ids come from paths."""
    out = _draw(capsys, composite, "mermaid").splitlines()
    assert out[:3] == ["stateDiagram-v2", "    [*] --> pick", "    state pick {"]
    pick = _block(out, "    state pick {")
    assert pick[0] == "        [*] --> pick_above"
    assert '        state "above" as pick_above' in pick
    assert "        pick_above --> pick_down : left_tool.reached and left_tool.position_error #lt; 2 mm" \
        in pick
    assert "        __any_pick --> pick_missed : elapsed #gt; 15 s" in pick
    assert "        pick_arrived --> [*]" in pick
    both = _block(out, "    state both {")
    assert both.count("        --") == 1
    divider = both.index("        --")
    left, right = " ".join(both[:divider]), " ".join(both[divider + 1:])
    assert "both_left_above" in left and "both_right" not in left
    assert "both_right_above" in right and "both_left" not in right
    assert "    pick --> pick : pick.missed and pick.visits #lt; 3" in out
    assert out.count("    __any --> failed : controller.failed") == 1


def test_mermaid_ids_unlike_mermaid_start_and_end(composite, capsys):
    """A state named ``end`` in ``carry`` is not Mermaid's own ``carry_end``."""
    out = _draw(capsys, composite, "mermaid").splitlines()
    carry = _block(out, "    state carry {")
    assert '        state "end" as carry_end_2' in carry
    assert "        carry_up --> carry_end_2 : left_tool.reached" in carry
    assert "        carry_end_2 --> [*]" in carry


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
