"""Move BAZAR's arms to a posture, written directly against the controller API.

The arms follow a joint-position task with an online trajectory (otg) and a
proportional feedback loop, under the joint kinematic limits and a velocity limit on
both Hankamp tools. The loop integrates the command (``q += dq * dt``), as a
simulated robot would, until the trajectory is completed and the arms are on it
(the tools' velocity limit can make them lag behind the trajectory), then prints
the reached posture.

Usage: ``python examples/hankamp_debug.py``
"""

from __future__ import annotations

import numpy as np

from robocop_dsl.control import Controller, OTGInterpolator, ProportionalFeedback
from robocop_dsl.world import load_world

TOOLS = ("bazar_left_hankamp_tool_object_side", "bazar_right_hankamp_tool_object_side")
TARGET = np.array([0, 0.25, 0, -2, 0, 0.7, 0, 0, 0.25, 0, -2, 0, 0.7, 0]) + 0.2
TOLERANCE = 1e-4
TIMEOUT = 30.0


def main() -> int:
    world = load_world("bazar/sophia.yaml")
    controller = Controller.from_world(world)
    controller.add_constraint("joint_kinematic", "joint_limits", "bazar_upper_joints",
                              max_velocity=1.0, max_acceleration=5.0)
    for tool in TOOLS:
        controller.add_constraint("body_velocity", f"{tool}_velocity", tool,
                                  max_linear=0.5, max_angular=1.0)
    arms = controller.add_task("joint_position", "arms", "bazar_arms", target=TARGET,
                               interpolator=OTGInterpolator(max_velocity=1.0,
                                                            max_acceleration=1.0),
                               feedback=ProportionalFeedback(gain=5.0))
    arms.enable()

    q = world.initial_configuration()
    indices = controller.joint_group.q_indices
    time = 0.0
    while not (arms.reached and arms.error < TOLERANCE) and time < TIMEOUT:
        result = controller.compute(q)
        if not result.solved:
            print(f"t = {time:.3f} s: no command ({result.reason})")
            return 1
        q[indices] += result.velocity * controller.time_step
        controller.update_state(q)
        time += controller.time_step
    posture = q[world.joint_group("bazar_arms").q_indices]
    print(f"trajectory completed in {time:.3f} s, error {arms.error:.2e} rad")
    print("reached posture [rad]:", np.array2string(posture, precision=4))
    return 0 if arms.reached and arms.error < TOLERANCE else 1


if __name__ == "__main__":
    raise SystemExit(main())
