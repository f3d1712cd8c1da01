"""``examples/perception.py``: a detection moves the part with ``runner.set_pose`` and
the pickup grasps it where it was seen, kinematic and in physics."""

import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize("world", [None, "bazar/sophia_physics.yaml"])
def test_the_pickup_grasps_the_part_where_the_camera_saw_it(world):
    extra = ["--world", world] if world else []
    done = subprocess.run([sys.executable, str(REPO / "examples" / "perception.py"), *extra],
                          capture_output=True, text=True, cwd=REPO)
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.strip() == ("outcome: success; part seen at [0.7, 0.26, 0.76], "
                                   "grasped at [0.7, 0.26, 0.76]")


def test_set_pose_refuses_a_body_a_joint_carries():
    from robocop_dsl.runtime import load_mission

    runner = load_mission(REPO / "missions" / "pickup.mission").runner()
    runner.step()
    with pytest.raises(ValueError, match="carried by a joint"):
        runner.set_pose("bazar_left_hankamp_tool_object_side", [[1, 0, 0, 0], [0, 1, 0, 0],
                                                                [0, 0, 1, 0], [0, 0, 0, 1]])
