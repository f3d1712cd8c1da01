"""A mission against the robot simulator process: losing it mid-run takes the
mission's failure path, the robot holds and the log is complete."""

import numpy as np

from robocop_dsl.drivers import LoopbackDriver
from robocop_dsl.runtime import Observer, RunLogger, load_mission, read_events, read_timeseries

MISSION = """mission loopback
world "bazar/sophia.yaml"
task arms: joint_position(bazar_arms) {
    interpolator = otg(max_velocity = 0.5 rad/s, max_acceleration = 1 rad/s^2)
}
state move {
    enter {
        enable arms
        arms.target = [0, 0.25, 0, -2, 0, 0.7, 0, 0, 0.25, 0, -2, 0, 0.7, 0] rad
    }
    when arms.reached -> done
}
when controller.failed -> failed
final done
final failed: failure
"""


class KillSimulator(Observer):
    """Kills the simulator process once the run has gone ``after`` cycles."""

    def __init__(self, driver, after):
        self.driver, self.after = driver, after

    def on_cycle(self, record):
        if record.cycle == self.after:
            self.driver.simulator.kill()


def test_losing_the_robot_takes_the_failure_path(tmp_path):
    path = tmp_path / "loopback.mission"
    path.write_text(MISSION)
    mission = load_mission(path)
    driver = LoopbackDriver(mission.world, "bazar_upper_joints", launch=True)
    runner = mission.runner(driver=driver)
    runner.add_observer(RunLogger(tmp_path / "log", runner.joint_names))
    runner.add_observer(KillSimulator(driver, 100))
    result = runner.run(duration=20, realtime=True)
    assert (result.outcome, result.final_state) == ("failure", "failed")
    assert result.transitions[-1].condition == "controller.failed"
    events = read_events(tmp_path / "log")
    kinds = [e["kind"] for e in events]
    assert kinds[0] == "start" and "fault" in kinds and kinds[-1] == "end"
    fault = next(e for e in events if e["kind"] == "fault")
    assert fault["message"].startswith("driver:")
    assert events[-1]["holding"] is True
    data = read_timeseries(tmp_path / "log")
    assert len(data["time"]) == result.cycles
    assert data["state"][-1] == "failed"
    moving = np.abs(np.diff(data["q.bazar_left_joint_4"][:100])).max()
    assert moving > 0
