"""What force sensing and force control cost a control cycle: the Panda's hand pressing
10 N on the table (``panda/panda_press.yaml``, MuJoCo), in one process.

The press is run once (a body_force task on the hand's z, a position task on the tool and
an orientation task below it, strict hierarchy) and 150 of its states in contact are
kept: the configuration and MuJoCo's state. Each row then replays them on a controller
of its own: the physics is put back at the state (``mj_forward``: its contacts and their
forces), and the cycle timed is what the run does after the driver's step: the force
sensors read (the contact wrench of the hand, then the filter) and the QP controller.

- ``tasks``: the position, orientation and finger tasks and the joint limits;
- ``+ sensor``: the same, the hand's force sensor read every cycle;
- ``+ body_force``: the same tasks and a body_force task on the hand's z reading a
  constant force (no sensor);
- ``+ sensor + body_force``: the force task reading the sensor, as in the run.

The rows run in turns, each replaying the kept states once; a row's ratio is the median
over the turns of its median over the base row's in the same turn (a shared machine's
load changes between turns, seldom within one).

Usage: ``python bench/force_cost.py [--turns N] [--cpu K]``
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np
from rich.console import Console
from rich.table import Table

from robocop_dsl.control import Controller
from robocop_dsl.runtime import load_mission
from robocop_dsl.runtime.sensors import Sensors

HAND, PRESS, GAIN, MAX_VELOCITY = "panda_hand", 10.0, 0.001, 0.05
KEPT = 150
MISSION = """
mission press "Press the table with the Panda's hand."
world "panda/panda_press.yaml"
constraint limits: joint_kinematic(panda_arm) {
    max_velocity     = 90 deg/s
    max_acceleration = 4 rad/s^2
}
task fingers: joint_position(panda_gripper) {
    target  = [0] cm
    enabled = true
}
task tcp: body_position(panda_hand_tcp) {
    interpolator = otg(max_velocity = 0.2 m/s, max_acceleration = 0.5 m/s^2)
    feedback     = proportional(gain = 5)
    tolerance    = 2 mm
    priority     = 1
}
task down: body_orientation(panda_hand) {
    feedback = proportional(gain = 5)
    target   = [180, 0, 0] deg
    priority = 1
}
state approach {
    enter {
        enable tcp, down
        tcp.target = [0.45, 0.15, 0.775] m
    }
    when tcp.reached -> press
    when elapsed > 10 s -> failed
}
state press { when elapsed > 5 s -> done }
final done
final failed: failure
"""


class Constant:
    """A force sensor that always reads the target: the task without the physics."""

    def wrench(self, body):
        return np.array([0.0, 0.0, -PRESS, 0.0, 0.0, 0.0])


def pressing_states(mission) -> tuple:
    """The run's runner and its last :data:`KEPT` states in contact: ``(q, qpos, qvel,
    act)`` each."""
    runner = mission.runner(hierarchy="strict")
    press = runner.controller.add_task("body_force", "press", HAND, target=[0, 0, -PRESS],
                                       axes="z", gain=GAIN, max_velocity=MAX_VELOCITY)
    data, kept = runner.driver.data, []
    while runner.step():
        if runner.state == "press" and not press.enabled:
            press.enable()
        if runner.state == "press" and runner.wrench(HAND)[2] < -1.0:
            kept.append((runner.q.copy(), data.qpos.copy(), data.qvel.copy(),
                         data.act.copy()))
    runner.finish()
    return runner, kept[-KEPT:]


def controller(runner, force: bool, sensors):
    """A controller of the run's tasks (plus a body_force task when ``force``)."""
    made = Controller.from_world(runner.controller.world, hierarchy="strict")
    made.sensors = sensors
    made.add_constraint("joint_kinematic", "limits", "panda_arm",
                        max_velocity=np.radians(90), max_acceleration=4.0)
    original = {task.name: task for task in runner.controller.tasks()}
    for name, body in (("tcp", "panda_hand_tcp"), ("down", HAND)):
        task = made.add_task(original[name].kind, name, body, priority=1, gain=5.0,
                             target=original[name].target)
        task.enable()
    made.add_task("joint_position", "fingers", "panda_gripper", target=[0.0]).enable()
    if force:
        made.add_task("body_force", "press", HAND, target=[0, 0, -PRESS], axes="z",
                      gain=GAIN, max_velocity=MAX_VELOCITY).enable()
    return made


def rows(runner) -> dict:
    """Each row: its controller and whether it reads the physics' sensor."""
    sensors = Sensors(runner.controller.world)
    return {
        "tasks": (controller(runner, False, None), None),
        "+ sensor": (controller(runner, False, sensors), sensors),
        "+ body_force": (controller(runner, True, Constant()), None),
        "+ sensor + body_force": (controller(runner, True, sensors), sensors),
    }


def turn(driver, states, made, sensors, period: float) -> list:
    """The cycle times [s] of one controller over the kept states."""
    model, data = driver.model, driver.data
    times = []
    for q, qpos, qvel, act in states:
        data.qpos[:], data.qvel[:], data.act[:] = qpos, qvel, act
        mujoco.mj_forward(model, data)
        driver.contacts.invalidate()
        started = time.perf_counter()
        if sensors is not None:
            sensors.update(driver, period)
        made.compute(q)
        times.append(time.perf_counter() - started)
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--turns", type=int, default=20)
    parser.add_argument("--cpu", type=int, default=0, help="the core to run on")
    args = parser.parse_args()
    os.sched_setaffinity(0, {args.cpu})
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "press.mission"
        path.write_text(MISSION)
        runner, states = pressing_states(load_mission(path))
    driver, period = runner.driver, runner.time_step
    made = rows(runner)
    medians: dict = {name: [] for name in made}
    for name, (control, sensors) in made.items():       # warm-up: first allocations
        turn(driver, states[:10], control, sensors, period)
    for _ in range(args.turns):
        for name, (control, sensors) in made.items():
            medians[name].append(statistics.median(turn(driver, states, control, sensors,
                                                        period)))
    base = medians["tasks"]
    table = Table(title=f"Panda pressing 10 N on the table: one control cycle after the "
                        f"physics step, {len(states)} states in contact, {args.turns} "
                        f"turns (cpu {args.cpu})")
    for column in ("cycle", "median", "ratio to tasks", "added"):
        table.add_column(column, justify="left" if column == "cycle" else "right")
    for name, times in medians.items():
        ratio = statistics.median(t / b for t, b in zip(times, base))
        added = statistics.median(t - b for t, b in zip(times, base))
        table.add_row(name, f"{statistics.median(times) * 1e6:.0f} µs", f"{ratio:.3f}",
                      f"{added * 1e6:+.1f} µs")
    Console().print(table)


if __name__ == "__main__":
    main()
