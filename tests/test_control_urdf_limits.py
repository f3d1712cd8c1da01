"""The URDF's velocity limits bound every command, whatever the mission asks."""

import numpy as np

from robocop_dsl.control import Controller


def test_commands_stay_within_the_urdf_velocity_limits_without_a_constraint(panda):
    """A posture 2 rad away with a gain of 50/s asks for 100 rad/s; with no
    joint_kinematic constraint the Panda still gets at most its URDF limits, and
    saturates them."""
    control = Controller.from_world(panda)
    group = panda.joint_group("panda_arm")
    q = panda.initial_configuration()
    target = group.positions(q) + 2.0
    control.add_task("joint_position", "posture", "panda_arm", target=target,
                     gain=50.0).enable()
    result = control.compute(q)
    assert result.solved
    assert np.all(np.abs(result.velocity) <= group.max_velocity + 1e-9)
    np.testing.assert_allclose(np.abs(result.velocity), group.max_velocity, rtol=1e-6)
