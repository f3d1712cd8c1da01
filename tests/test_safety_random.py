"""Randomised missions written to break the safety layer (see ``safety_missions.py``)
run through the command line on BAZAR and the Panda; every logged cycle, the stop
included, keeps the controller's promises, recomputed from the log: positions within
the limits, collision pairs at least ``min_distance`` apart, velocities and
accelerations within their limits (an acceleration over its limit only in a cycle that
announces a ``constraint_relaxed``), finite values, and no fault but the one a mission
without a ``controller.failed`` clause asks for when a cycle was relaxed."""

import pytest

from robocop_dsl.cli.main import main

from safety_missions import ROBOTS, check_run, safety_case

SEEDS = range(6)


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("robot", ["bazar", "panda"])
def test_promises_hold(robot, seed, tmp_path, capsys):
    """A generated mission's run keeps every promise, whatever the mission asks."""
    case = safety_case(robot, seed)
    path = case.write(tmp_path)
    code = main(["run", str(path), "--log", str(tmp_path / "log")])
    output = capsys.readouterr()
    figures = check_run(tmp_path / "log", case.limits)
    report = (f"{robot} seed {seed} (safety_case({robot!r}, {seed})): exit {code}\n"
              f"{figures.report()}\n{output.out[-2000:]}{output.err[-2000:]}")
    if case.fault_expected(figures):
        assert code in (0, 1, 3) and figures.outcome in ("success", "failure", "fault"), report
    else:
        assert code in (0, 1) and figures.outcome != "fault", report
    assert figures.violations == {}, report


def test_generated_missions_pass_check(tmp_path, capsys):
    """Forty generated missions per robot pass ``check``."""
    paths = [str(safety_case(robot, seed).write(tmp_path))
             for robot in ROBOTS for seed in range(40)]
    assert main(["check", *paths]) == 0, capsys.readouterr().err
