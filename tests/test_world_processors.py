"""The ``processors:`` of a world are checked when it loads: types, options, values,
required options, RoboCoP's option names, and the driver each qp_controller commands."""

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from robocop_dsl.diagnostics import DiagnosticError
from robocop_dsl.drivers import create_driver
from robocop_dsl.runtime.driver import SimulatedDriver
from robocop_dsl.world import load_world

REPO = Path(__file__).resolve().parent.parent
CONTROLLER = "c: {type: qp_controller, options: {joint_group: bazar_arms, time_step: 5ms}}"
TINY = 'mission tiny\nworld "w.yaml"\nstate wait { when elapsed > 50 ms -> done }\nfinal done\n'


def world_file(tmp_path, processors: str) -> Path:
    """``tmp_path/w.yaml``: the BAZAR work cell with the given ``processors:`` block."""
    path = tmp_path / "w.yaml"
    path.write_text("models:\n  - include: bazar/workcell.yaml\nprocessors:\n"
                    + textwrap.indent(textwrap.dedent(processors).strip("\n"), "  ") + "\n")
    return path


def problem(tmp_path, processors: str):
    """The only diagnostic of a world with the given processors."""
    path = world_file(tmp_path, processors)
    with pytest.raises(DiagnosticError) as caught:
        load_world(path)
    [diagnostic] = caught.value.diagnostics
    assert diagnostic.file == str(path)
    return diagnostic


def at(diagnostic, code: str, line: int, token: str) -> bool:
    """Whether ``diagnostic`` is a ``code`` at ``token`` on world-file line ``line``."""
    column = diagnostic.source_line.index(token) + 1
    return (diagnostic.code, diagnostic.span.line, diagnostic.span.column) == (code, line, column)


def robocop(*args):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", *map(str, args)],
                          capture_output=True, text=True, cwd=REPO)


@pytest.mark.parametrize("processors, located, message, hint", [
    ("v: {type: meshcatt, options: {period: 40ms}}", ("unknown-processor-type", "meshcatt"),
     "unknown processor type 'meshcatt'", "did you mean 'meshcat'?"),
    ("v: {type: meshcat, options: {perod: 40ms}}", ("unknown-option", "perod"),
     "unknown option 'perod' of a meshcat processor", "did you mean 'period'?"),
    ("c: {type: qp_controller, options: {joint_group: bazar_arms, timestep: 5ms}}",
     ("unknown-option", "timestep"), "unknown option 'timestep'", "did you mean 'time_step'?"),
    ("c: {type: qp_controller, options: {joint_group: bazar_arms}}",
     ("missing-option", "options"), "processor 'c' (qp_controller) needs option 'time_step'",
     "time_step: 5ms"),
    ("c: {type: qp_controller, options: {time_step: 5ms}}",
     ("missing-option", "options"), "needs option 'joint_group'", "joint_group: NAME"),
    ("c: {type: qp_controller, options: {joint_group: bazar_arms, time_step: 0ms}}",
     ("wrong-option", "0ms"), "'time_step' must be a duration > 0, not 0ms", "5ms"),
    ("c: {type: qp_controller, options: {joint_group: bazar_arms, time_step: 5 min}}",
     ("wrong-option", "5 min"), "must be a duration > 0, not 5 min", "with a unit"),
    ("v: {type: meshcat, options: {period: -0.04}}", ("wrong-option", "-0.04"),
     "'period' must be a duration > 0", "with a unit"),
    ("c: {type: qp_controller, options: {joint_group: bazar_arms, time_step: 5ms, "
     "solver: proxsqp}}", ("wrong-option", "proxsqp"), "unknown solver 'proxsqp'",
     "did you mean 'proxqp'? (installed solvers: "),
    ("c: {type: qp_controller, options: {joint_group: bazar_arms, time_step: 5ms, "
     "hierarchy: hierarchical}}", ("wrong-option", "hierarchical"),
     "'hierarchy' must be strict or weighted, not hierarchical", None),
    ("c: {type: qp_controller, options: {joint_group: bazar_arm, time_step: 5ms}}",
     ("unknown-joint", "bazar_arm,"), "unknown joint group or joint 'bazar_arm'",
     "did you mean 'bazar_arms'?"),
    ("d: {type: simulated, options: {joint_group: bazar_arms, rate: 0Hz}}",
     ("wrong-option", "0Hz"), "'rate' must be a rate > 0, not 0Hz", "1kHz"),
    ("d: {type: simulated, options: {joint_group: bazar_arms, rate: 1kHz, period: 1ms}}",
     ("wrong-option", "period"), "either 'rate' or 'period'", "remove one"),
    ("d: {type: loopback, options: {joint_group: bazar_arms, port: 99999}}",
     ("wrong-option", "99999"), "must be a TCP port", None),
    ("d: {type: loopback, options: {joint_group: bazar_arms}}",
     ("missing-option", "options"), "needs option 'port' or 'launch: true'", "launch: true"),
    ("m: {type: model, options: {implementation: rbdyn}}", ("wrong-option", "rbdyn"),
     "'implementation' must be pinocchio, not rbdyn", None),
    ("m: {type: model, option: {implementation: pinocchio}}", ("invalid-entry", "option"),
     "unknown key 'option'", "did you mean 'options'?"),
])
def test_each_problem_is_located_with_a_hint(tmp_path, processors, located, message, hint):
    """Every processor mistake is one diagnostic at its line and column, with a hint."""
    diagnostic = problem(tmp_path, processors)
    assert at(diagnostic, located[0], 4, located[1])
    assert message in diagnostic.message
    assert hint is None or hint in diagnostic.hint
    assert diagnostic.source_line.strip() == processors


def test_world_and_check_report_processor_problems(tmp_path):
    """``world`` and ``check`` print the located diagnostic, caret and hint included."""
    world_file(tmp_path, "c: {type: qp_controller, options: {joint_group: bazar_arms}}")
    (tmp_path / "m.mission").write_text(TINY)
    shown, checked = robocop("world", tmp_path / "w.yaml"), robocop("check", tmp_path / "m.mission")
    for done in (shown, checked):
        assert done.returncode == 1
        assert f"{tmp_path / 'w.yaml'}:4:28: error[missing-option]" in done.stdout + done.stderr
        assert "^^^^^^^" in done.stdout + done.stderr
        assert "for example time_step: 5ms" in done.stdout + done.stderr


def test_velocity_output_true_runs(tmp_path):
    """RoboCoP's ``velocity_output: true`` says what this controller does: accepted,
    dropped from the controller's options, and the mission runs."""
    world_file(tmp_path, """
        c: {type: qp_controller, options: {joint_group: bazar_arms, time_step: 5ms,
                                           velocity_output: true, force_output: false,
                                           include_bias_force_in_command: false}}
        d: {type: simulated, options: {joint_group: bazar_arms}}
    """)
    assert load_world(tmp_path / "w.yaml").processors["c"].options == {
        "joint_group": "bazar_arms", "time_step": 0.005}
    (tmp_path / "m.mission").write_text(TINY)
    done = robocop("run", tmp_path / "m.mission")
    assert done.returncode == 0, done.stderr
    assert "outcome: success" in done.stdout


@pytest.mark.parametrize("option, hint", [
    ("velocity_output: false", "outputs joint velocities only"),
    ("force_output: true", "outputs joint velocities only"),
    ("include_bias_force_in_command: true", "sends no force command"),
])
def test_robocop_options_we_do_not_support_are_refused(tmp_path, option, hint):
    """A RoboCoP option asking for what this controller does not do is refused."""
    diagnostic = problem(tmp_path, "c: {type: qp_controller, options: {joint_group: "
                                   f"bazar_arms, time_step: 5ms, {option}}}}}")
    assert at(diagnostic, "unsupported-option", 4, option.split()[1] + "}")
    assert diagnostic.message == f"'{option}' is not supported"
    assert hint in diagnostic.hint


def test_several_drivers_and_none_named_is_an_error(tmp_path):
    diagnostic = problem(tmp_path, f"""
        {CONTROLLER}
        a: {{type: simulated, options: {{joint_group: bazar_arms}}}}
        b: {{type: simulated, options: {{joint_group: bazar_arms}}}}
    """)
    assert at(diagnostic, "ambiguous-driver", 4, "c:")
    assert diagnostic.message == ("several driver processors drive 'bazar_arms', the joint "
                                  "group of 'c': a, b")
    assert diagnostic.hint == "name the one it commands in its options: driver: a"


@pytest.mark.parametrize("driver, message, hint", [
    ("bb", "no driver processor 'bb'", "did you mean 'b'?"),
    ("head", "driver 'head' drives 'bazar_ptu', not 'bazar_arms'", "drivers on 'bazar_arms': a, b"),
])
def test_a_named_driver_must_drive_the_controllers_group(tmp_path, driver, message, hint):
    diagnostic = problem(tmp_path, f"""
        c: {{type: qp_controller, options: {{joint_group: bazar_arms, time_step: 5ms,
                                           driver: {driver}}}}}
        a: {{type: simulated, options: {{joint_group: bazar_arms}}}}
        b: {{type: simulated, options: {{joint_group: bazar_arms}}}}
        head: {{type: simulated, options: {{joint_group: bazar_ptu}}}}
    """)
    assert at(diagnostic, "wrong-option", 5, f"{driver}}}")
    assert (diagnostic.message, diagnostic.hint) == (message, hint)


def test_the_only_driver_on_the_group_is_the_controllers(tmp_path):
    """Other drivers elsewhere do not make the choice ambiguous."""
    world = load_world(world_file(tmp_path, f"""
        {CONTROLLER}
        arms: {{type: simulated, options: {{joint_group: bazar_arms}}}}
        head: {{type: simulated, options: {{joint_group: bazar_ptu}}}}
    """))
    assert world.processors["c"].driver == "arms"
    driver = create_driver(world, realtime=False, time_step=0.005, controller="c")
    assert isinstance(driver, SimulatedDriver) and driver.group.name == "bazar_arms"


def test_two_drivers_and_a_named_one_run(tmp_path):
    """``driver: b`` picks the simulated driver over the loopback one (which has no
    simulator to reach), and the mission runs to success."""
    world_file(tmp_path, """
        c: {type: qp_controller, options: {joint_group: bazar_arms, time_step: 5ms,
                                           driver: b}}
        a: {type: loopback, options: {joint_group: bazar_arms, port: 9, connect_timeout: 50ms}}
        b: {type: simulated, options: {joint_group: bazar_arms}}
    """)
    assert load_world(tmp_path / "w.yaml").processors["c"].driver == "b"
    (tmp_path / "m.mission").write_text(TINY)
    assert robocop("check", "--strict", tmp_path / "m.mission").returncode == 0
    done = robocop("run", tmp_path / "m.mission")
    assert done.returncode == 0, done.stderr
    assert "outcome: success" in done.stdout
