"""Every shipped mission runs to success on its real world; composed missions show their
active configurations."""

from pathlib import Path

import pytest

from robocop_dsl.lang import ast, parse_file
from robocop_dsl.runtime import Observer, load_mission

REPO = Path(__file__).resolve().parent.parent
MISSIONS = [p for p in sorted((REPO / "missions").glob("*.mission"))
            if parse_file(p).mission.first(ast.MissionHeader) is not None]


class States(Observer):
    wants_tasks = False

    def __init__(self):
        self.states = []

    def on_cycle(self, record):
        if not self.states or self.states[-1] != record.state:
            self.states.append(record.state)


def run(path):
    runner = load_mission(path).runner()
    seen = States()
    runner.add_observer(seen)
    return runner.run(duration=180.0), seen.states


@pytest.mark.parametrize("path", MISSIONS, ids=lambda p: p.stem)
def test_mission_runs_to_success(path):
    """Headless, on the world it names, the mission reaches a success final."""
    result, _ = run(path)
    assert result.outcome == "success", result.message


def test_parallel_regions_advance_independently():
    """In dual_arm_parallel one arm's region reaches its outcome while the other arm is
    still moving, and the head's region finishes on its own."""
    result, states = run(REPO / "missions" / "dual_arm_parallel.mission")
    assert result.outcome == "success"
    both = [s.split(" | ") for s in states if s.startswith("both/")]
    assert all(len(leaves) == 3 for leaves in both)
    left_first = [s for s in both if s[0] == "both/left/arrived"
                  and s[1] in ("both/right/above", "both/right/down")]
    right_first = [s for s in both if s[1] == "both/right/arrived"
                   and s[0] in ("both/left/above", "both/left/down")]
    assert left_first or right_first
    assert any(s[2] == "both/head/seen" and s[0] != "both/left/arrived" for s in both)


def test_two_parts_goes_through_both_transfers():
    """Each transfer's nested approach shows in the configuration, in order."""
    result, states = run(REPO / "missions" / "two_parts.mission")
    assert result.outcome == "success"
    firsts = [s for s in states if s.startswith(("first/", "second/"))]
    assert firsts[0] == "first/take/above"
    assert "first/put_down" in firsts and "second/take/down" in firsts
    assert firsts.index("first/put_down") < firsts.index("second/take/above")
    assert [t.target for t in result.transitions if "/" not in t.source] == [
        "first", "second", "back", "done"]
