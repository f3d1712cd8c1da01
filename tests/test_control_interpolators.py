"""Interpolators and feedback loops, on their own."""

import numpy as np
import pytest

from robocop_dsl.control import (InvalidParameter, PIDFeedback, ProportionalFeedback,
                                 UnknownKind, make_feedback_loop, make_interpolator)

DT = 0.005


def run(interpolator, start, target, steps=20000, velocity=None):
    interpolator.setup(len(start), DT, np.zeros(len(start), dtype=bool))
    interpolator.restart(np.array(start, float),
                         np.zeros(len(start)) if velocity is None else np.array(velocity))
    interpolator.target = np.array(target, float)
    positions, velocities = [], []
    for _ in range(steps):
        position, rate = interpolator.step()
        positions.append(position.copy())
        velocities.append(rate.copy())
        if interpolator.finished:
            break
    return np.array(positions), np.array(velocities)


def test_otg_reaches_target_within_limits():
    """otg ends exactly on the target without exceeding its velocity and acceleration."""
    otg = make_interpolator("otg", max_velocity=[1.0, 0.5], max_acceleration=2.0)
    positions, velocities = run(otg, [0.0, 0.0], [1.0, -0.3])
    assert otg.finished
    np.testing.assert_allclose(positions[-1], [1.0, -0.3], atol=1e-9)
    assert np.all(np.abs(velocities) <= np.array([1.0, 0.5]) + 1e-9)
    accelerations = np.diff(velocities, axis=0) / DT
    assert np.all(np.abs(accelerations) <= 2.0 + 1e-6)


def test_otg_jerk_and_target_velocity():
    """otg honours a jerk limit and arrives with the requested velocity."""
    otg = make_interpolator("otg", max_velocity=1.0, max_acceleration=2.0, max_jerk=10.0,
                            target_velocity=0.2)
    positions, velocities = run(otg, [0.0], [1.0])
    assert otg.finished
    assert velocities[-1][0] == pytest.approx(0.2, abs=1e-9)
    jerks = np.diff(velocities[:, 0], 2) / DT**2
    assert np.max(np.abs(jerks)) <= 10.0 + 1e-3


def test_otg_angular_limits_apply_to_rotation_coordinates():
    """max_angular_velocity bounds the coordinates flagged angular, the others keep theirs
    (coordinates are time-synchronised, so the far angular one sets the pace)."""
    otg = make_interpolator("otg", max_velocity=0.1, max_acceleration=1.0,
                            max_angular_velocity=1.0, max_angular_acceleration=1.0)
    otg.setup(2, DT, np.array([False, True]))
    otg.restart(np.zeros(2), np.zeros(2))
    otg.target = np.array([0.01, 5.0])
    peak = np.zeros(2)
    while not otg.finished:
        peak = np.maximum(peak, np.abs(otg.step()[1]))
    assert peak[0] <= 0.1 + 1e-9 and 0.1 < peak[1] <= 1.0 + 1e-9


@pytest.mark.parametrize("kind", ["linear", "cubic", "quintic"])
def test_timed_interpolators_take_their_duration(kind):
    """linear/cubic/quintic reach the target after exactly their duration."""
    interpolator = make_interpolator(kind, duration=0.5)
    positions, velocities = run(interpolator, [0.0, 1.0], [1.0, 0.0])
    assert len(positions) == round(0.5 / DT)
    np.testing.assert_allclose(positions[-1], [1.0, 0.0], atol=1e-12)
    if kind != "linear":
        np.testing.assert_allclose(velocities[-1], 0.0, atol=1e-9)


def test_none_passes_target_through():
    """none is finished at once and returns the target."""
    interpolator = make_interpolator(None)
    positions, _ = run(interpolator, [0.0], [3.0])
    assert interpolator.finished and positions[-1][0] == 3.0


def test_restart_begins_from_given_state():
    """restart begins a new trajectory from the given position and velocity."""
    otg = make_interpolator("otg", max_velocity=1.0, max_acceleration=1.0)
    run(otg, [0.0], [1.0])
    otg.restart(np.array([2.0]), np.array([0.5]))
    position, velocity = otg.step()
    assert position[0] > 2.0 and not otg.finished


def test_interpolator_errors_carry_data():
    """Unknown kinds list the registered ones; bad parameters name themselves."""
    with pytest.raises(UnknownKind) as error:
        make_interpolator("spline")
    assert "otg" in error.value.available
    with pytest.raises(InvalidParameter) as error:
        make_interpolator("linear", duration=-1.0)
    assert error.value.parameter == "duration"
    assert repr(make_interpolator("otg", max_velocity=1.0, max_acceleration=2.0)) == \
        "otg(max_velocity=1.0, max_acceleration=2.0)"


def test_proportional_scalar_and_per_axis():
    """proportional multiplies the error by a scalar or per-axis gain."""
    loop = make_feedback_loop("proportional", gain=2.0)
    loop.setup(3, DT)
    np.testing.assert_allclose(loop.compute(np.array([1.0, -1.0, 0.5])), [2.0, -2.0, 1.0])
    loop.gain = [1.0, 2.0, 3.0]
    np.testing.assert_allclose(loop.compute(np.ones(3)), [1.0, 2.0, 3.0])
    with pytest.raises(InvalidParameter):
        ProportionalFeedback(gain=-1.0)


def test_pid_integral_and_derivative():
    """pid adds the integral and the finite-difference derivative of the error."""
    loop = PIDFeedback(kp=1.0, ki=10.0, kd=0.1)
    loop.setup(1, DT)
    first = loop.compute(np.array([1.0]))
    assert first[0] == pytest.approx(1.0 + 10.0 * DT)
    second = loop.compute(np.array([2.0]))
    assert second[0] == pytest.approx(2.0 + 10.0 * 3 * DT + 0.1 * 1.0 / DT)
    loop.reset()
    assert loop.compute(np.array([0.0]))[0] == 0.0
