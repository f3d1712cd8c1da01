"""The collision constraints of one controller share one scene: each gets exactly the
rows, bounds and pairs it would get alone, through enabling, disabling, retuning and
removing the others."""

import numpy as np
import pytest

from robocop_dsl.control import Controller

GROUP = "bazar_upper_joints"
OVER = [-0.15, 1.2, 0, -2.0, 0, -1.6, 0, 0.15, 1.2, 0, -1.4, 0, 1.0, 0]
"""Both arms bent down over the workbench, turned towards each other, the left tool
folded back: 6 shape pairs within 25 cm of the workbench, 15 between the arms, 11 in
the left arm."""
SETS = {"bench": ("bazar_arms", "workbench"), "arms": ("bazar_left_arm", "bazar_right_arm"),
        "self": ("bazar_left_arm", "bazar_left_arm")}


def _configuration(world):
    q = world.initial_configuration()
    q[world.joint_group("bazar_arms").q_indices] = OVER
    return q


def _controller(world, names, **parameters):
    controller = Controller(world, GROUP, 0.005)
    constraints = {name: controller.add_constraint(
        "collision_avoidance", name, SETS[name][0], other=SETS[name][1],
        **{"influence": 0.25, **parameters.get(name, {})}) for name in names}
    return controller, constraints


def _rows(controller, constraint, q, velocity):
    """The constraint's pairs, rows and lower bounds at ``q`` with the previous command
    ``velocity``."""
    controller.state.previous_command = velocity
    controller.update_state(q)
    constraint.rows
    jacobian = constraint.compute_jacobian(controller.state)
    lower, _ = constraint.compute_bounds(controller.state)
    count = constraint.pairs_near
    pairs = [(w.first.name, w.second.name) for w in constraint.witnesses]
    return pairs, jacobian[:count].copy(), lower[:count].copy()


def _alone(world, name, q, velocity, **parameters):
    controller, constraints = _controller(world, [name], **{name: parameters})
    return _rows(controller, constraints[name], q, velocity)


def _same(found, expected):
    """The same pairs, bounds and rows; the rows to 1e-3 m/s per rad/s: two upper arms
    side by side are nearly parallel cylinders, whose closest points coal's GJK may place
    anywhere on a segment of them (the distances agree to its tolerance, 1e-6 m)."""
    assert found[0] == expected[0]
    np.testing.assert_allclose(found[1], expected[1], atol=1e-3)
    np.testing.assert_allclose(found[2], expected[2], atol=1e-5)


def test_shared_constraints_get_what_each_gets_alone(bazar):
    """Three constraints of one controller, one scene: each one's pairs, rows and bounds
    are those it has in a controller of its own."""
    q = _configuration(bazar)
    velocity = np.random.default_rng(3).normal(scale=0.2, size=16)
    controller, constraints = _controller(bazar, SETS)
    assert len({id(c.watch.scene) for c in constraints.values()}) == 1
    for name, constraint in constraints.items():
        found = _rows(controller, constraint, q, velocity)
        assert found[0], f"{name}: no pair within influence"
        _same(found, _alone(bazar, name, q, velocity))
    assert sum(c.pairs_checked for c in constraints.values()) == \
        constraints["bench"].watch.scene.size


def test_disabling_retuning_and_removing_one_leaves_the_others_alone(bazar):
    """A disabled constraint has no row and the others keep theirs; a new influence or
    damping takes effect at the next cycle; a removed one takes its pairs away."""
    q = _configuration(bazar)
    velocity = np.zeros(16)
    controller, constraints = _controller(bazar, SETS)
    constraints["arms"].disable()
    assert _rows(controller, constraints["arms"], q, velocity)[0] == []
    _same(_rows(controller, constraints["bench"], q, velocity),
          _alone(bazar, "bench", q, velocity))
    constraints["arms"].enable()
    constraints["arms"].configure(influence=0.1, damping=2.0)
    _same(_rows(controller, constraints["arms"], q, velocity),
          _alone(bazar, "arms", q, velocity, influence=0.1, damping=2.0))
    checked = constraints["self"].pairs_checked
    controller.remove_constraint("bench")
    assert constraints["self"].watch.scene.size == checked + constraints["arms"].pairs_checked
    for name in ("arms", "self"):
        _same(_rows(controller, constraints[name], q, velocity),
              _alone(bazar, name, q, velocity,
                     **({"influence": 0.1, "damping": 2.0} if name == "arms" else {})))


def test_each_controller_has_its_own_watch(bazar):
    """Two controllers on one world never share a scene (a cascade's controllers each
    follow their own kinematics)."""
    first, a = _controller(bazar, ["bench"])
    second, b = _controller(bazar, ["bench"])
    assert a["bench"].watch is not b["bench"].watch
    q = _configuration(bazar)
    near = _rows(first, a["bench"], q, np.zeros(16))
    assert _rows(second, b["bench"], bazar.initial_configuration(), np.zeros(16))[0] == []
    assert _rows(first, a["bench"], q, np.zeros(16))[0] == near[0]


@pytest.mark.parametrize("name", sorted(SETS))
def test_rows_come_in_the_order_of_the_witnesses(bazar, name):
    """Row ``i`` of a constraint belongs to its witness ``i``: its bound is the damper's
    at that witness's distance."""
    q = _configuration(bazar)
    controller, constraints = _controller(bazar, [name])
    constraint = constraints[name]
    pairs, jacobian, lower = _rows(controller, constraint, q, np.zeros(16))
    for witness, bound in zip(constraint.witnesses, lower):
        assert bound == pytest.approx(-5.0 * (witness.distance - 0.01))
    assert len(pairs) == len(jacobian) == len(lower)


def test_rows_follow_the_robot_while_the_same_pairs_stay_near(bazar):
    """Moving a little at a time, the same pairs stay within influence and what depends
    on them alone is kept from state to state; the rows still are those of the state
    (the controlled columns of BAZAR's upper joints are not a slice of the model's: the
    Jacobian's columns are taken again at each state)."""
    q = _configuration(bazar)
    controller, constraints = _controller(bazar, ["bench", "self"])
    arms = bazar.joint_group("bazar_arms").q_indices
    direction = np.random.default_rng(7).normal(size=len(arms))
    state = controller.state
    assert not isinstance(state.columns, slice)
    kept, previous = 0, None
    for _ in range(10):
        q = q.copy()
        q[arms] += 1e-5 * direction
        for name in ("bench", "self"):
            constraint = constraints[name]
            _, jacobian, _ = _rows(controller, constraint, q, np.zeros(16))
            seen = constraint.watch.seen
            kept += seen.nearby.pairs is previous
            previous = seen.nearby.pairs
            scene = constraint.watch.scene
            kept_key, kept_basis = scene._basis_key, scene._basis
            scene._basis_key = ()       # the rows again, from nothing kept
            fresh = scene.distance_rows(seen.nearby, state.columns)
            scene._basis_key, scene._basis = kept_key, kept_basis
            first = constraint._span[0]
            np.testing.assert_allclose(jacobian, fresh[first:first + len(jacobian)], atol=1e-12)
    assert kept >= 15, "the same pairs were not followed from state to state"


def test_runs_one_after_the_other_leave_nothing_behind():
    """A finished run's controller, its collision watch and scene and its copy of the
    world are freed: a campaign running jobs in one process does not grow (a table of
    watches keyed weakly by a state its values referred to used to keep every run)."""
    import gc
    import weakref

    from robocop_dsl.control.constraints.collision_watch import collision_watch
    from robocop_dsl.runtime import load_mission

    mission = load_mission("missions/pickup.mission")
    kept = []
    for _ in range(3):
        runner = mission.runner()
        runner.run(duration=0.02)
        state = runner.controller.state
        kept += [weakref.ref(state), weakref.ref(collision_watch(state).scene),
                 weakref.ref(state.world)]
        del runner, state
    gc.collect()
    assert [ref() for ref in kept] == [None] * len(kept)


def test_the_bounds_follow_the_velocity_and_the_limits_at_one_configuration(bazar):
    """The robot still (one configuration, one kinematic state), a new command or a new
    table of acceleration limits changes the bounds: each time they are those of a
    controller that sees that state for the first time."""
    q = _configuration(bazar)
    rng = np.random.default_rng(5)
    slow, fast = rng.normal(scale=0.2, size=16), rng.normal(scale=3.0, size=16)
    controller, constraints = _controller(bazar, ["bench"])
    bench = constraints["bench"]
    before = _rows(controller, bench, q, slow)
    found = _rows(controller, bench, q, fast)
    assert not np.allclose(found[2], before[2])
    _same(found, _alone(bazar, "bench", q, fast))
    weak = np.full(16, 0.01)      # rad/s^2: the joints can hardly brake
    controller.state.max_acceleration = weak
    found = _rows(controller, bench, q, fast)
    fresh, alone = _controller(bazar, ["bench"])
    fresh.state.max_acceleration = weak.copy()
    _same(found, _rows(fresh, alone["bench"], q, fast))
    assert not np.allclose(found[2], _alone(bazar, "bench", q, fast)[2])
