"""The safety layer's pieces, each against what it promises: viable bounds that stop in
time in discrete time, the joint box, relaxation in its documented order, the braking
QP, and the package importable on its own."""

import subprocess
import sys

import numpy as np
import pytest

from robocop_dsl.control import Controller
from robocop_dsl.safety import JointBox, JointLimits, approach_speed, viable_speed

STEP = 0.005


@pytest.mark.parametrize("distance, acceleration", [(0.3, 2.0), (0.01, 5.0), (1.2, 0.5)])
def test_braking_from_the_viable_speed_stops_before_the_limit(distance, acceleration):
    """Held at the viable speed until braking must start, then braking at the
    acceleration limit every period, the joint stops before the limit, and the bound
    never asks for more than that acceleration."""
    position, speed, ahead = 0.0, 0.0, distance
    while True:
        bound = float(approach_speed(ahead, acceleration, STEP))
        assert bound >= speed - acceleration * STEP - 1e-12
        speed = min(bound, speed + acceleration * STEP)
        position += speed * STEP
        ahead = distance - position
        assert ahead >= -1e-12
        if speed <= 0.0:
            break


def test_a_speed_above_the_viable_bound_is_asked_to_brake_not_to_jump():
    """A limit that comes within reach while moving fast: the bound asks for braking at
    most at the hard braking share of the acceleration limit, while that still stops."""
    speed = float(approach_speed(0.05, 0.5 * 4.0, STEP)) + 0.1
    bound = float(viable_speed(0.05, speed, 4.0, STEP))
    assert speed - 4.0 * STEP <= bound < speed


def limits(lower, upper, velocity=1.0, acceleration=4.0):
    n = len(lower)
    return JointLimits(np.array(lower, float), np.array(upper, float), np.full(n, velocity),
                       np.full(n, acceleration), ("world",) * n)


def test_a_joint_past_its_limit_goes_no_further_and_comes_back_within_its_acceleration():
    box = JointBox(limits([-1.0], [1.0]), STEP)
    lower, upper = np.zeros(1), np.zeros(1)
    box.write(np.array([1.2]), np.array([0.0]), lower, upper)
    assert upper[0] == pytest.approx(-4.0 * STEP) and lower[0] == pytest.approx(-1.0)
    box.write(np.array([1.2]), np.array([0.3]), lower, upper)
    assert upper[0] == 0.0      # moving out: stop, no further
    relaxed = box.accelerations(np.array([0.3]), lower, upper, ("joint",))
    assert [r.unit for r in relaxed] == ["rad/s^2"] and lower[0] == upper[0] == 0.0


def test_inside_its_limits_a_joint_may_always_hold_still():
    rng = np.random.default_rng(0)
    box = JointBox(limits([-1.0] * 50, [1.0] * 50), STEP)
    lower, upper = np.zeros(50), np.zeros(50)
    box.write(rng.uniform(-1, 1, 50), rng.uniform(-1, 1, 50), lower, upper)
    assert np.all(lower <= 0.0) and np.all(upper >= 0.0)


def test_body_velocity_is_relaxed_before_acceleration(panda):
    """A body velocity bound of zero while a joint must move to stay within its limits
    (it starts outside the mission's range, moving at its previous command): the body
    bound is relaxed, the acceleration limit is not."""
    controller = Controller(panda, "panda_arm", 0.002)
    q = panda.initial_configuration()
    group = panda.joint_group("panda_arm")
    lowest = group.lower.copy()
    lowest[1] = q[group.q_indices][1] + 0.2
    controller.add_constraint("joint_kinematic", "limits", "panda_arm", min_position=lowest,
                              max_acceleration=50.0)
    controller.add_constraint("body_velocity", "still", "panda_hand", max_linear=0.0)
    result = controller.compute(q)
    assert result.status == "relaxed"
    assert [r.constraint for r in result.relaxations] == ["body_velocity 'still'"]
    assert result.velocity[1] == pytest.approx(50.0 * 0.002)


def test_the_braking_qp_slows_every_joint_at_its_limit(panda):
    controller = Controller(panda, "panda_arm", 0.002)
    controller.add_constraint("joint_kinematic", "limits", "panda_arm", max_acceleration=5.0)
    q = panda.initial_configuration()
    controller.compute(q)
    controller.state.previous_command = np.array([0.5, -0.5, 0.02, 0.0, 0.3, -0.004, 0.1])
    result = controller.brake(q)
    np.testing.assert_allclose(result.velocity, [0.49, -0.49, 0.01, 0.0, 0.29, 0.0, 0.09],
                               atol=1e-7)


def test_the_safety_package_imports_on_its_own():
    done = subprocess.run([sys.executable, "-c", "import robocop_dsl.safety"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
