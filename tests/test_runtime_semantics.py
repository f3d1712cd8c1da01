"""The cycle semantics on the real BAZAR world: order of actions, guards, timeouts,
events, attach/detach and the controller-failure path."""

import textwrap

import numpy as np
import pytest

from robocop_dsl.runtime import Observer, load_mission

HEADER = 'world "bazar/sophia.yaml"\n'


def mission(tmp_path, body, name="m"):
    path = tmp_path / f"{name}.mission"
    path.write_text(f"mission {name}\n{HEADER}" + textwrap.dedent(body))
    return load_mission(path)


class Events(Observer):
    def __init__(self):
        self.events = []
        self.records = []

    def on_event(self, event):
        self.events.append(event)

    def on_cycle(self, record):
        self.records.append(record)


def run(mission_, duration=30.0, **options):
    runner = mission_.runner(**options)
    seen = Events()
    runner.add_observer(seen)
    return runner, runner.run(duration=duration), seen


def test_exit_actions_run_before_the_next_enter(tmp_path):
    m = mission(tmp_path, """
        state first {
            enter { log "enter first" }
            exit  { log "exit first" }
            when elapsed >= 50 ms -> second
        }
        state second {
            enter { log "enter second" }
            when elapsed >= 50 ms -> done
        }
        final done
    """)
    _, result, seen = run(m)
    kinds = [(e.kind, e.data.get("message") or e.data.get("to")) for e in seen.events
             if e.kind in ("log", "transition")]
    assert kinds == [("log", "enter first"), ("transition", "second"), ("log", "exit first"),
                     ("log", "enter second"), ("transition", "done")]
    assert result.outcome == "success"
    assert [t.time for t in result.transitions] == [0.05, 0.1]


@pytest.mark.parametrize("own, expected", [("elapsed >= 100 ms", "own"),
                                           ("elapsed >= 1 s", "guarded")])
def test_state_clauses_come_before_guards(tmp_path, own, expected):
    m = mission(tmp_path, f"""
        state wait {{
            when {own} -> own
        }}
        when time >= 100 ms -> guarded
        final own
        final guarded: failure
    """)
    _, result, _ = run(m)
    assert result.final_state == expected
    assert result.transitions[0].time == 0.1
    assert result.outcome == ("success" if expected == "own" else "failure")


def test_timeout_with_elapsed(tmp_path):
    """A slow motion that cannot finish in 0.5 s takes the timeout branch at 0.5 s."""
    m = mission(tmp_path, """
        task arms: joint_position(bazar_arms) {
            interpolator = otg(max_velocity = 0.05 rad/s, max_acceleration = 1 rad/s^2)
        }
        state move {
            enter {
                enable arms
                arms.target = [0, 0.25, 0, -2, 0, 0.7, 0, 0, 0.25, 0, -2, 0, 0.7, 0] rad
            }
            when arms.reached -> done
            when elapsed > 500 ms -> failed
        }
        final done
        final failed: failure
    """)
    _, result, seen = run(m)
    assert (result.final_state, result.outcome) == ("failed", "failure")
    assert result.transitions[0].time == pytest.approx(0.505)
    moved = seen.records[-1].positions - seen.records[0].positions
    assert 0 < np.abs(moved).max() <= 0.05 * 0.5 + 1e-6


def test_emitted_and_injected_events(tmp_path):
    """An event raised in a cycle is seen from the next; one injected between cycles
    counts as raised in the last completed cycle, so the next cycle sees it."""
    m = mission(tmp_path, """
        event go "raised by the operator"
        state a {
            enter { emit ready }
            when event ready -> b
        }
        state b {
            when event go -> done
            when elapsed > 1 s -> failed
        }
        final done
        final failed: failure
    """)
    runner = m.runner()
    runner.step()
    assert runner.state == "a"
    runner.step()
    assert runner.state == "b"
    for _ in range(20):
        runner.step()
    assert runner.state == "b"
    runner.emit("go")
    runner.step()
    assert runner.state == "done"
    result = runner.run()
    assert [(t.time, t.condition) for t in result.transitions] == [
        (0.005, "event ready"), (0.11, "event go")]


def test_events_stay_raised_until_the_owner_state_is_left(tmp_path):
    """``go``, raised in cycle 0, is still seen 50 ms later by ``wait`` (entered before
    the raise), not by ``late`` (entered after it)."""
    m = mission(tmp_path, """
        state wait {
            enter { emit go }
            when event go and elapsed >= 50 ms -> late
        }
        state late {
            when event go -> failed
            when elapsed >= 50 ms -> done
        }
        final done
        final failed: failure
    """)
    _, result, _ = run(m)
    assert [(t.source, t.target, t.time) for t in result.transitions] == [
        ("wait", "late", 0.05), ("late", "done", 0.1)]


SQUEEZE = "enter { below.max_position = [-1, -1, -1, -1, -1, -1, -1] rad }"
INFEASIBLE = """
    constraint above: joint_kinematic(bazar_left_arm) {
        min_position = [1, 1, 1, 1, 1, 1, 1] rad
    }
    constraint below: joint_kinematic(bazar_left_arm)
    state hold {
        %s
        when elapsed > 1 s -> done
    }
    final done
""" % SQUEEZE
"""Two ranges that leave the arm no position from the first cycle on, one of them set by
the start state's action (declared ones that clash are refused by ``check``)."""


def test_infeasible_constraints_take_the_failure_path(tmp_path):
    m = mission(tmp_path, INFEASIBLE + """
        when controller.failed -> failed
        final failed: failure
    """)
    runner, result, seen = run(m)
    assert (result.final_state, result.outcome) == ("failed", "failure")
    assert result.transitions[0].condition == "controller.failed"
    assert result.qp_failures == 1
    assert not seen.records[0].solved and not seen.records[0].command.any()
    assert [e.kind for e in seen.events].count("qp_failure") == 1


def test_a_failure_without_handler_is_a_fault_and_holds(tmp_path):
    m = mission(tmp_path, INFEASIBLE)
    runner, result, seen = run(m)
    assert result.outcome == "fault" and result.final_state == "hold"
    assert "no QP solution" in result.message
    assert all(not r.command.any() for r in seen.records)
    start = seen.records[0].positions
    assert all(np.array_equal(r.positions, start) for r in seen.records)


def test_pickup_carries_the_part_to_the_drop_point(tmp_path):
    m = load_mission("missions/pickup.mission")
    runner, result, seen = run(m)
    assert result.outcome == "success"
    assert [t.target for t in result.transitions if "/" not in t.source] == [
        "approach", "grasp", "lift", "move_to_drop", "release", "return", "done"]
    drop = runner.kinematics.body_pose("drop_point")
    np.testing.assert_allclose(runner.kinematics.body_pose("part_body").translation,
                               drop.translation, atol=1e-3)
    carried = [r for r in seen.records
               if r.state.split("/")[0] in ("lift", "move_to_drop", "release")]
    assert carried and all("part_body" in r.body_poses for r in carried)
    lifted = carried[len(carried) // 2].body_poses["part_body"][:3, 3]
    assert lifted[2] > 0.76 + 0.1
    assert not seen.records[-1].body_poses


# ---- nested machines, behaviours, parallel regions (one cycle is 5 ms) ----------------

def logged(seen, cycle=None):
    """The log messages and transitions (``A -> B``) in the order they happened."""
    lines = []
    for event in seen.events:
        if cycle is not None and event.cycle != cycle:
            continue
        if event.kind == "log":
            lines.append(event.data["message"])
        elif event.kind == "transition":
            lines.append(f"{event.data['from']} -> {event.data['to']}")
    return lines


def fired(seen):
    """``(cycle, source, target)`` of every transition."""
    return [(e.cycle, e.data["from"], e.data["to"]) for e in seen.events
            if e.kind == "transition"]


def test_enter_during_exit_and_transition_actions_across_three_levels(tmp_path):
    m = mission(tmp_path, """
        state outer {
            enter  { log "enter outer" }
            during { log "during outer" }
            exit   { log "exit outer" }
            state mid {
                enter  { log "enter mid" }
                during { log "during mid" }
                exit   { log "exit mid" }
                state inner {
                    enter  { log "enter inner" }
                    during { log "during inner" }
                    exit   { log "exit inner" }
                }
            }
            when elapsed >= 10 ms -> other { log "between" }
        }
        state other {
            enter { log "enter other" }
            when elapsed >= 10 ms -> done
        }
        final done
    """)
    _, result, seen = run(m)
    assert logged(seen, 0) == ["enter outer", "enter mid", "enter inner",
                               "during outer", "during mid", "during inner"]
    assert logged(seen, 2) == ["outer -> other", "exit inner", "exit mid", "exit outer",
                               "between", "enter other"]
    assert [r.state for r in seen.records[:3]] == ["outer/mid/inner"] * 2 + ["other"]
    assert seen.records[0].transitions[0].entered == ("outer", "outer/mid",
                                                      "outer/mid/inner")
    assert seen.records[2].transitions[0].exited == ("outer/mid/inner", "outer/mid",
                                                     "outer")
    log_states = {e.data["message"]: e.data["state"] for e in seen.events if e.kind == "log"}
    assert log_states["exit mid"] == "outer/mid" and log_states["between"] == "outer"
    assert result.outcome == "success"


def test_inner_clauses_come_before_the_clauses_around_them(tmp_path):
    """In cycle 2 the clauses of ``pick/above`` and of ``pick`` both hold: the inner one
    fires, ``pick``'s waits for a cycle where nothing inside fires; the mission's guard
    comes last."""
    m = mission(tmp_path, """
        state pick {
            state above { when elapsed >= 10 ms -> down }
            state down  { when elapsed >= 1 s -> above }
            when elapsed >= 10 ms -> carry
        }
        state carry { when elapsed >= 1 s -> done }
        when time >= 10 ms -> failed
        final done
        final failed: failure
    """)
    _, result, seen = run(m)
    assert fired(seen) == [(2, "pick/above", "pick/down"), (3, "pick", "carry"),
                           (4, "carry", "failed")]
    assert result.final_state == "failed"


APPROACH = """
    behavior approach() {
        start above
        state above { when elapsed >= 10 ms -> down }
        state down  { when elapsed >= 1 s -> arrived }
        when elapsed > 15 ms -> missed
        final arrived
        final missed
    }
"""


def test_elapsed_counts_from_the_entry_of_the_state_that_owns_the_clause(tmp_path):
    """The behaviour's guard (``elapsed > 15 ms``) counts from the entry of its active
    state ``down`` (cycle 2), the instance's own clause from the instance's entry."""
    m = mission(tmp_path, APPROACH + """
        state pick: approach() {
            when elapsed >= 40 ms -> late
        }
        final late
    """)
    _, result, seen = run(m)
    assert fired(seen) == [(2, "pick/above", "pick/down"), (6, "pick/down", "pick/missed"),
                           (8, "pick", "late")]


def test_visits_count_re_entries_and_restart_with_their_machine(tmp_path):
    """``go`` runs twice per entry of ``pick``, ``pick`` three times."""
    m = mission(tmp_path, """
        state pick {
            state go {
                enter { log "go" }
                when elapsed >= 10 ms -> back
            }
            state back {
                when go.visits < 2 -> go
                when elapsed >= 0 s -> missed
            }
            final missed
            when pick.missed and pick.visits < 3 -> pick { log "retry" }
            when pick.missed -> failed
        }
        final failed: failure
    """)
    _, result, seen = run(m)
    assert logged(seen).count("go") == 6 and logged(seen).count("retry") == 2
    assert [line for line in logged(seen) if line in ("go", "retry")] == [
        "go", "go", "retry", "go", "go", "retry", "go", "go"]
    assert (result.final_state, result.outcome) == ("failed", "failure")


PARALLEL = APPROACH + """
    state both: parallel {
        enter { log "enter both" }
        exit  { log "exit both" }
        region left: approach()
        region right {
            state above {
                exit { log "exit right/above" }
                when elapsed >= 10 ms -> down
            }
            state down { when elapsed >= 20 ms -> arrived }
            final arrived
        }
        when both.left.missed and both.right.arrived -> missed
        when both.done -> finish
    }
    final finish
    final missed: failure
"""


def test_regions_step_in_declaration_order_in_the_same_cycle(tmp_path):
    """Both regions leave ``above`` in cycle 2, left first; the configuration shows both
    regions' states; leaving the parallel state exits the right region first."""
    m = mission(tmp_path, PARALLEL)
    _, result, seen = run(m)
    assert logged(seen, 0) == ["enter both"]
    assert fired(seen) == [(2, "both/left/above", "both/left/down"),
                           (2, "both/right/above", "both/right/down"),
                           (6, "both/left/down", "both/left/missed"),
                           (6, "both/right/down", "both/right/arrived"),
                           (7, "both", "missed")]
    assert [r.state for r in seen.records[1:4]] == [
        "both/left/above | both/right/above", "both/left/down | both/right/down",
        "both/left/down | both/right/down"]
    assert seen.records[-1].transitions[0].exited == (
        "both/right/arrived", "both/left/missed", "both")
    assert (result.final_state, result.outcome) == ("missed", "failure")


def test_a_parallel_state_is_done_when_every_region_is_final(tmp_path):
    m = mission(tmp_path, PARALLEL.replace("when elapsed > 15 ms -> missed",
                                           "when elapsed >= 20 ms -> arrived"))
    _, result, seen = run(m)
    assert fired(seen)[-1] == (7, "both", "finish")
    assert seen.records[6].state == "both/left/arrived | both/right/arrived"
    assert result.final_state == "finish"


def test_a_failure_is_handled_only_by_clauses_checked_in_the_configuration(tmp_path):
    """The behaviour's guard handles the failure while its machine runs; once it is in a
    final state, no checked clause tests ``controller.failed``: the next failure is a
    fault."""
    constraints = INFEASIBLE[:INFEASIBLE.index("state hold")]
    m = mission(tmp_path, constraints + """
        behavior careful() {
            state wait { when elapsed > 1 s -> calm }
            final calm
            final broken
            when controller.failed -> broken
        }
        state hold: careful() {
            %s
            when hold.calm -> done
        }
        final done
    """ % SQUEEZE)
    _, result, seen = run(m)
    assert fired(seen) == [(1, "hold/wait", "hold/broken")]
    assert result.transitions[0].condition == "controller.failed"
    assert (result.outcome, result.final_state) == ("fault", "hold/broken")
