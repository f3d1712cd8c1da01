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
    for _ in range(3):
        runner.step()
    assert runner.state == "b"
    assert runner.time == pytest.approx(0.015)
    for _ in range(20):
        runner.step()
    assert runner.state == "b"
    runner.emit("go")
    runner.step()
    assert runner.state == "done"
    result = runner.run()
    assert [t.condition for t in result.transitions] == ["event ready", "event go"]


INFEASIBLE = """
    constraint above: joint_kinematic(bazar_left_arm) {
        min_position = [1, 1, 1, 1, 1, 1, 1] rad
    }
    constraint below: joint_kinematic(bazar_left_arm) {
        max_position = [-1, -1, -1, -1, -1, -1, -1] rad
    }
    state hold {
        when elapsed > 1 s -> done
    }
    final done
"""


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
    assert [t.target for t in result.transitions] == [
        "approach", "grasp", "lift", "move_to_drop", "release", "return", "done"]
    drop = runner.kinematics.body_pose("drop_point")
    np.testing.assert_allclose(runner.kinematics.body_pose("part_body").translation,
                               drop.translation, atol=1e-3)
    carried = [r for r in seen.records if r.state in ("lift", "move_to_drop", "release")]
    assert carried and all("part_body" in r.body_poses for r in carried)
    lifted = carried[len(carried) // 2].body_poses["part_body"][:3, 3]
    assert lifted[2] > 0.76 + 0.1
    assert not seen.records[-1].body_poses
