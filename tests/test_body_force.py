"""The body_force task: its reference velocity is the bounded admittance law along the
axes it controls; in physics the Panda's hand holds 10 N against the table, recomputed
from the logged force columns, under a strict hierarchy (a position task below keeps
the tool on its x/y target) and a weighted one; `check` reads its parameters."""

import textwrap

import numpy as np
import pyarrow.parquet as pq
import pytest

from robocop_dsl.compile import check_file
from robocop_dsl.control import Controller, InvalidParameter
from robocop_dsl.control.exceptions import PartFailed
from robocop_dsl.runtime import Observer, RunLogger, load_mission, read_timeseries
from robocop_dsl.runtime.plot import figures
from robocop_dsl.world import load_world

TARGET_XY = (0.45, 0.15)
PRESS = 10.0            # [N] the force the hand exerts on the table, downwards
GAIN = 0.001            # [(m/s)/N]
MAX_VELOCITY = 0.05     # [m/s]
MISSION = f"""
mission press "Press the table with the Panda's hand."

world "panda/panda_press.yaml"

constraint limits: joint_kinematic(panda_arm) {{
    max_velocity     = 90 deg/s
    max_acceleration = 4 rad/s^2
}}

task fingers: joint_position(panda_gripper) {{
    target  = [0] cm
    enabled = true
}}

task tcp: body_position(panda_hand_tcp) {{
    interpolator = otg(max_velocity = 0.2 m/s, max_acceleration = 0.5 m/s^2)
    feedback     = proportional(gain = 5)
    tolerance    = 2 mm
    priority     = 1
}}

task down: body_orientation(panda_hand) {{
    feedback = proportional(gain = 5)
    target   = [180, 0, 0] deg
    priority = 1
}}

state approach {{
    enter {{
        enable tcp, down
        tcp.target = [{TARGET_XY[0]}, {TARGET_XY[1]}, 0.775] m
    }}
    when tcp.reached -> press
    when elapsed > 10 s -> failed
}}

state press {{
    ENTER
    when elapsed > 5 s -> done
}}

final done
final failed: failure
"""


class Fixed:
    """Force sensors that read what the test says."""

    def __init__(self, **wrenches):
        self.wrenches = {body: np.asarray(w, dtype=float) for body, w in wrenches.items()}

    def wrench(self, body):
        return self.wrenches[body]


class Poses(Observer):
    """The tool's world position at each cycle, and the cycle's state."""

    wants_tasks = False

    def __init__(self, world):
        self.world, self.rows = world, []

    def on_cycle(self, record):
        position = self.world.body_pose("panda_hand_tcp", record.q).translation
        self.rows.append((record.time, record.state, *position))


def pressing_run(folder, hierarchy: str, axes, enter: str = ""):
    """The press mission run with a body_force task on the hand, enabled from Python
    when the state ``press`` starts; its log folder and the tool's positions."""
    path = folder / "press.mission"
    path.write_text(MISSION.replace("ENTER", enter))
    mission = load_mission(path)
    runner = mission.runner(hierarchy=hierarchy)
    press = runner.controller.add_task("body_force", "press", "panda_hand",
                                       target=[0, 0, -PRESS], axes=axes, gain=GAIN,
                                       max_velocity=MAX_VELOCITY)
    poses = Poses(mission.world)
    runner.add_observer(RunLogger(folder / "log", runner.joint_names))
    runner.add_observer(poses)
    while runner.step():
        if runner.state == "press" and not press.enabled:
            press.enable()
    assert runner.finish().outcome == "success"
    return folder / "log", np.array([r[2:] for r in poses.rows]), [r[1] for r in poses.rows]


def last_second_of_contact(data: dict) -> np.ndarray:
    """The cycles of the last second of the state ``press``, all of them in contact."""
    pressing = np.flatnonzero(np.asarray(data["state"]) == "press")
    last = pressing[data["time"][pressing] > data["time"][pressing[-1]] - 1.0]
    assert (data["force.panda_hand.z"][last] < -1.0).all(), "the hand left the table"
    return last


@pytest.fixture(scope="module")
def strict(tmp_path_factory):
    return pressing_run(tmp_path_factory.mktemp("strict"), "strict", ["z"])


def test_the_hand_holds_ten_newtons_on_the_table(strict):
    """Median of the logged force over the last second of contact: -10 N within 1 N
    (what the hand exerts on the table: downwards)."""
    log, _, _ = strict
    data = read_timeseries(log)
    last = last_second_of_contact(data)
    assert np.median(data["force.panda_hand.z"][last]) == pytest.approx(-PRESS, abs=1.0)
    assert np.median(data["error.press"][last]) < 1.0
    assert (data["reference.press.2"][last] == -PRESS).all()


def test_a_position_task_below_keeps_the_tool_on_its_xy_target(strict):
    """Strict hierarchy: the force task takes z, the position task below holds x and y
    within 2 mm of its target all through the contact."""
    log, positions, states = strict
    data = read_timeseries(log)
    touching = (np.asarray(states) == "press") & (data["force.panda_hand.z"] < -1.0)
    assert touching.sum() > 200
    assert np.abs(positions[touching, :2] - TARGET_XY).max() < 2e-3


def test_the_log_and_the_plot_show_the_sensor(strict):
    log, _, _ = strict
    schema = pq.read_schema(log / "timeseries.parquet")
    units = {f.name: f.metadata[b"unit"].decode() for f in schema
             if f.metadata and b"unit" in f.metadata}
    assert units["force.panda_hand.z"] == "N" and units["torque.panda_hand.x"] == "Nm"
    assert units["error.press"] == "N"
    drawn = dict(figures(log))
    assert [ax.get_title(loc="left") for ax in drawn["forces"].axes[1:]] == [
        "force sensor on panda_hand"]
    assert any(ax.get_title(loc="left") == "force error [N]"
               for ax in drawn["task_errors"].axes[1:])


def test_weighted_the_hand_presses_and_yields_sideways(tmp_path):
    """Weighted hierarchy, every axis controlled (target [0, 0, -10] N), the position
    task disabled: -10 N down within 1 N, under 1 N sideways."""
    log, _, _ = pressing_run(tmp_path, "weighted", [0, 1, 2], "enter { disable tcp }")
    data = read_timeseries(log)
    last = last_second_of_contact(data)
    assert np.median(data["force.panda_hand.z"][last]) == pytest.approx(-PRESS, abs=1.0)
    for axis in "xy":
        assert abs(np.median(data[f"force.panda_hand.{axis}"][last])) < 1.0


# ---- the task in the controller -------------------------------------------------------


@pytest.fixture(scope="module")
def world():
    return load_world("panda/panda_press.yaml")


def controller_with(world, measured, **parameters):
    controller = Controller.from_world(world, hierarchy="weighted")
    controller.sensors = Fixed(panda_hand=np.r_[measured, 0, 0, 0])
    task = controller.add_task("body_force", "press", "panda_hand", gain=GAIN,
                               max_velocity=MAX_VELOCITY, **parameters)
    task.enable()
    return controller, task


@pytest.mark.parametrize("measured, velocity", [
    ([0, 0, 0], -GAIN * PRESS),             # in the air: down at gain x 10 N
    ([3, 1, -4], -GAIN * 6),                # 6 N short of the target
    ([0, 0, -200], MAX_VELOCITY),           # far too hard: up, bounded
])
def test_the_reference_velocity_is_the_bounded_admittance(world, measured, velocity):
    controller, task = controller_with(world, measured, target=[0, 0, -PRESS], axes="z")
    q = world.initial_configuration()
    result = controller.compute(q)
    jacobian = controller.state.jacobian(task.body_id)
    assert task.compute_jacobian(controller.state).shape == (1, controller.state.dofs)
    assert (jacobian[2] @ result.velocity) == pytest.approx(velocity, rel=1e-3)
    assert task.error == pytest.approx(abs(-PRESS - measured[2]))


def test_reached_within_the_tolerance_of_every_controlled_axis(world):
    controller, task = controller_with(world, [0.4, -0.3, -9.2], target=[0, 0, -PRESS],
                                       tolerance=1.0)
    controller.compute(world.initial_configuration())
    assert task.reached and task.error == pytest.approx(np.linalg.norm([0.4, 0.3, 0.8]))
    task.target = [0, 1, -PRESS]
    assert not task.reached
    task.gain, task.max_velocity = 0.002, 0.01
    assert task.feedback_loop().parameters()["max_velocity"].tolist() == [0.01] * 3
    assert not task.positional


def test_without_sensors_the_task_says_what_it_needs(world):
    controller = Controller.from_world(world)
    controller.add_task("body_force", "press", "panda_hand", gain=GAIN,
                        max_velocity=MAX_VELOCITY).enable()
    with pytest.raises(PartFailed, match="body_force 'press' reads the force of "
                                         "'panda_hand', and the controller has no force "
                                         "sensors"):
        controller.compute(world.initial_configuration())


@pytest.mark.parametrize("axes", [["w"], [2, 2], [], [3]])
def test_axes_are_the_worlds_each_once(world, axes):
    controller = Controller.from_world(world)
    with pytest.raises(InvalidParameter, match="axes"):
        controller.add_task("body_force", "press", "panda_hand", axes=axes, gain=GAIN,
                            max_velocity=MAX_VELOCITY)


# ---- check --------------------------------------------------------------------------

DECLARED = """mission press
world "panda/panda_press.yaml"
task press: body_force(panda_hand) {
    PARAMETERS
}
state touch {
    enter { enable press }
    when press.reached -> done
}
final done
"""


def diagnostics(tmp_path, parameters: str) -> list:
    path = tmp_path / "m.mission"
    path.write_text(DECLARED.replace("PARAMETERS", textwrap.indent(
        textwrap.dedent(parameters).strip(), "    ").strip()))
    return [(d.code, d.message, d.hint) for d in check_file(path).diagnostics]


def test_check_accepts_a_force_task(tmp_path):
    assert diagnostics(tmp_path, """
        target       = [0, 0, -10] N
        axes         = [x, z]
        gain         = 2 (mm/s)/N
        max_velocity = 5 cm/s
        tolerance    = 500 mN
    """) == []


@pytest.mark.parametrize("parameters, expected", [
    ("axes = [w]", ("unknown-axis", "unknown axis 'w'",
                    "for example [z] or [x, y]: the world's axes are x, y, z")),
    ("axes = [Z]", ("unknown-axis", "unknown axis 'Z'", "did you mean 'z'?")),
    ("axes = [x, x]", ("wrong-value", "'axes' lists axis 'x' twice", "list each axis once")),
    ("axes = [0, 2]", ("wrong-value", "'axes' expects a list of the world's axes",
                       "for example [z] or [x, y]: the world's axes are x, y, z")),
    ("target = [0, 0, -1] m", ("wrong-dimension", "'target' expects a force (N, kN, mN), "
                               "not a length", "a number without a unit is SI (N)")),
    ("gain = 2 N", ("wrong-dimension", "'gain' expects an admittance ((m/s)/N, (cm/s)/N, "
                    "(mm/s)/N), not a force", "a number without a unit is SI ((m/s)/N)")),
    ("tolerance = 1 mm", ("wrong-dimension", "'tolerance' expects a force (N, kN, mN), "
                          "not a length", "a number without a unit is SI (N)")),
])
def test_check_refuses_bad_parameters(tmp_path, parameters, expected):
    given = f"gain = 1 (mm/s)/N\nmax_velocity = 5 cm/s\n{parameters}"
    if parameters.startswith("gain"):
        given = f"max_velocity = 5 cm/s\n{parameters}"
    assert diagnostics(tmp_path, given) == [expected]


def test_check_needs_the_gain_and_the_bound(tmp_path):
    [(code, message, _)] = diagnostics(tmp_path, "axes = [z]")
    assert (code, message) == ("missing-parameter",
                               "task 'press' needs 'gain', 'max_velocity'")


def test_a_force_task_without_a_target_aims_at_zero_force(tmp_path):
    """Its kind's default, as the catalogue says: [0, 0, 0] N, not the force measured
    when it starts."""
    from robocop_dsl.compile import load_mission as compile_mission
    from robocop_dsl.compile import spec

    path = tmp_path / "yield.mission"
    path.write_text('mission yielding "Yield to whatever pushes the hand."\n'
                    'world "panda/panda_press.yaml"\n'
                    "task give: body_force(panda_hand) {\n"
                    "    gain = 0.001 (m/s)/N\n    max_velocity = 1 cm/s\n}\n"
                    "state s {\n    enter { enable give }\n    when give.reached -> done\n}\n"
                    "final done\n")
    assert compile_mission(path).tasks["give"].target == spec.VectorTarget((0.0, 0.0, 0.0))
