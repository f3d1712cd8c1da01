"""A camera tells the mission where the part is: ``runner.set_pose`` between cycles.

The pickup mission grasps the part at ``pickup_point``. Here a stand-in for a
perception pipeline "detects" the part 6 cm further along the workbench's y axis
while the arms go to their start posture, and moves both the part and its grasp
frame there before the next cycle. The mission then picks the part where it was seen,
and the script prints where the tool grasped it.

With a physics world (``--world bazar/sophia_physics.yaml``) the part is a free body:
``set_pose`` puts it there in the simulation, where it then rests.

Usage: ``python examples/perception.py [--world WORLD.yaml]``
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pinocchio as pin

from robocop_dsl.runtime import load_mission
from robocop_dsl.world import load_world

MISSION = Path(__file__).resolve().parent.parent / "missions" / "pickup.mission"
SEEN_AT = np.array([0.7, 0.26, 0.76])
"""Where the camera sees the part [m], in the world."""
TOOL = "bazar_left_hankamp_tool_object_side"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--world", help="a variant of the mission's world")
    args = parser.parse_args()
    mission = load_mission(MISSION, world=load_world(args.world) if args.world else None)
    runner = mission.runner()
    seen, grasped = False, None
    while runner.step():
        if not seen and runner.time >= 1.0:
            detection = pin.SE3(np.eye(3), SEEN_AT)
            runner.set_pose("part_body", detection)
            runner.set_pose("pickup_point", detection * pin.SE3(
                pin.rpy.rpyToMatrix(0, np.pi, 0), np.zeros(3)))
            seen = True
        if grasped is None and runner.state.startswith("lift"):
            grasped = runner.kinematics.body_pose(TOOL).translation.copy()
    result = runner.finish()
    print(f"outcome: {result.outcome}; part seen at {SEEN_AT.round(3).tolist()}, "
          f"grasped at {None if grasped is None else grasped.round(3).tolist()}")
    return 0 if result.outcome == "success" else 1


if __name__ == "__main__":
    raise SystemExit(main())
