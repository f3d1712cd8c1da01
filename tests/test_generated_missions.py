"""Property: missions generated for the bundled worlds (random parameter values within
their declared ranges, random targets among the world's bodies, random state graphs,
vars assigned from measures, conditions on vars, positions and forces) pass `check`
and run 500 cycles with no exception escaping the run: a fault is an outcome, never a
traceback. The Panda press world runs in physics, with a force sensor."""

import numpy as np
import pytest

from robocop_dsl.compile import WorldCache, check_file
from robocop_dsl.runtime import Observer, load_mission
from robocop_dsl.world import load_world

from mission_generator import MissionGenerator, Scene

WORLDS = ("panda/panda_on_table.yaml", "bazar/sophia.yaml", "kinova/jaco.yaml",
          "ur5/ur5_on_table.yaml", "panda/panda_press.yaml")
SEEDS = range(8)
CYCLES = 500
OUTCOMES = {"success", "failure", "fault", "stopped"}
CACHE = WorldCache()


@pytest.fixture(scope="module", params=WORLDS)
def scene(request):
    return Scene(load_world(request.param), request.param)


class Commands(Observer):
    """Every command of the run [rad/s or m/s]."""

    def __init__(self):
        self.commands = []

    def on_cycle(self, record):
        self.commands.append(record.command)


@pytest.mark.parametrize("seed", SEEDS)
def test_generated_missions_check_and_run(scene, seed, tmp_path):
    path = tmp_path / "generated.mission"
    path.write_text(MissionGenerator(scene, seed).mission())
    result = check_file(path, cache=CACHE)
    assert [d for d in result.diagnostics if d.severity == "error"] == [], path.read_text()
    mission = load_mission(path)
    runner = mission.runner()
    commands = Commands()
    runner.add_observer(commands)
    outcome = runner.run(duration=CYCLES * runner.time_step)
    assert outcome.outcome in OUTCOMES
    assert outcome.cycles >= CYCLES or outcome.outcome != "stopped"
    assert np.isfinite(np.array(commands.commands)).all()
    if outcome.outcome == "fault":
        assert outcome.message
