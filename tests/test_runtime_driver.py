"""The simulated driver integrates the last velocity command of its group."""

import numpy as np

from robocop_dsl.runtime.driver import SimulatedDriver


def test_starts_at_the_world_initial_posture(bazar):
    driver = SimulatedDriver(bazar, "bazar_upper_joints", 0.005)
    q, v = driver.read()
    np.testing.assert_allclose(q, bazar.initial_configuration())
    assert not v.any()


def test_integrates_the_command_of_its_group_only(bazar):
    group = bazar.joint_group("bazar_left_arm")
    driver = SimulatedDriver(bazar, "bazar_left_arm", 0.01)
    start, _ = driver.read()
    command = np.linspace(-0.7, 0.7, 7)
    driver.write(command)
    for _ in range(100):
        q, v = driver.read()
    np.testing.assert_allclose(q[group.q_indices] - start[group.q_indices], command * 1.0,
                               atol=1e-12)
    others = np.setdiff1d(np.arange(bazar.model.nq), group.q_indices)
    np.testing.assert_array_equal(q[others], start[others])
    np.testing.assert_allclose(v[group.v_indices], command)


def test_hold_stops_the_motion(bazar):
    driver = SimulatedDriver(bazar, "bazar_ptu", 0.005)
    driver.write([0.5, -0.5])
    driver.read()
    driver.hold()
    first, _ = driver.read()
    second, v = driver.read()
    np.testing.assert_array_equal(first, second)
    assert not v.any()
