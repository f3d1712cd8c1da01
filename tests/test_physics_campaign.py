"""How robust is the grasp: 50 physics variants of the Panda pick (cube position, mass,
friction) swept on two workers, the success rate with its interval, and a failed
variant rerun alone with the printed command, identically."""

import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from robocop_dsl.campaign import read_results
from robocop_dsl.campaign.summary import wilson_interval
from robocop_dsl.diagnostics import DiagnosticError
from robocop_dsl.campaign.jobs import load_campaign
from robocop_dsl.runtime import read_timeseries

from conftest import MISSIONS, write

REPO = Path(__file__).resolve().parent.parent
CAMPAIGN = MISSIONS / "panda_pick.campaign.yaml"


def cli(*args):
    return subprocess.run([sys.executable, "-m", "robocop_dsl", *map(str, args)],
                          capture_output=True, text=True, cwd=REPO)


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    output = tmp_path_factory.mktemp("sweep") / "results.parquet"
    done = cli("sweep", CAMPAIGN, "--workers", "2", "--output", output)
    return done, read_results(output).to_pylist()


def test_fifty_variants_on_two_workers_give_a_success_rate(swept):
    done, rows = swept
    assert len(rows) == 50 and {r["outcome"] for r in rows} <= {"success", "failure"}
    successes = sum(r["outcome"] == "success" for r in rows)
    assert 0 < successes < 50                   # the sweep finds where the grasp slips
    assert done.returncode == 1
    low, high = wilson_interval(successes, 50)
    assert f"{successes} ({successes / 50:.0%})" in done.stdout
    assert f"{low:.0%} to {high:.0%}" in done.stdout
    # each row names its draws; light cubes on sticky tables are held
    assert all(0.05 <= r["physics.friction"] <= 1.0 and 0.05 <= r["cube_body.mass"] <= 4.0
               and 0.47 <= r["cube_body.x"] <= 0.53 for r in rows)
    held = [r for r in rows if r["physics.friction"] * 40 > 3 * 9.81 * r["cube_body.mass"]]
    assert held and all(r["outcome"] == "success" for r in held)


def test_a_failed_variant_reruns_alone_identically(swept, tmp_path):
    """The printed rerun command gives the sweep's outcome, final state and mission
    time, the cube starts where the table says, and two reruns log the same numbers."""
    done, rows = swept
    failed = next(r for r in rows if r["outcome"] == "failure")
    command = next(line.split("rerun: ", 1)[1] for line in done.stdout.splitlines()
                   if line.strip().startswith("rerun:") and f"--job {failed['job']}" in line)
    argv = shlex.split(command)[1:]
    logs = []
    for attempt in range(2):
        again = cli(*argv, "--log", tmp_path / f"log{attempt}")
        assert again.returncode == 1, again.stdout + again.stderr
        assert f"mission time: {failed['mission_time']:.3f} s" in again.stdout
        assert f"final state: {failed['final_state']}" in again.stdout
        logs.append(read_timeseries(tmp_path / f"log{attempt}"))
    cube = [logs[0][f"pose.cube_body.{a}"][0] for a in "xy"]
    assert cube == pytest.approx([failed["cube_body.x"], failed["cube_body.y"]], abs=1e-4)
    for column in logs[0]:
        if column not in ("cycle_time", "compute_time"):
            assert np.array_equal(np.asarray(logs[0][column]), np.asarray(logs[1][column]),
                                  equal_nan=np.asarray(logs[0][column]).dtype.kind == "f")


def test_physics_varies_only_where_physics_runs(tmp_path):
    """Friction on a kinematic world and the mass of a fixed body: located errors."""
    path = write(tmp_path, "broken.campaign.yaml", f"""
        missions:
          - {MISSIONS / 'panda_reach.mission'}
          - {MISSIONS / 'panda_pick.mission'}
        vary:
          physics:
            friction: {{uniform: {{low: 0.2, high: 0.8}}}}
            mass:
              table: {{uniform: {{low: 1, high: 2}}}}
    """)
    with pytest.raises(DiagnosticError) as error:
        load_campaign(path)
    found = {(d.code, d.span.line if d.span else None, d.message)
             for d in error.value.diagnostics}
    assert found == {
        ("no-physics", 5, "'physics' varies, but panda_on_table.yaml simulates no physics"),
        ("body-not-free", 8, "cannot vary the mass of 'table' of world variant 'panda_pick': "
                             "it is not a free body")}


def test_a_mass_that_may_be_drawn_negative(tmp_path):
    path = write(tmp_path, "broken.campaign.yaml", f"""
        missions: [{MISSIONS / 'panda_pick.mission'}]
        vary:
          physics:
            mass:
              cube_body: {{uniform: {{low: -1, high: 2}}}}
    """)
    with pytest.raises(DiagnosticError) as error:
        load_campaign(path)
    (found,) = error.value.diagnostics
    assert (found.code, found.span.line, found.message) == (
        "wrong-value", 5, "'cube_body' must stay > 0: 'low' is -1")
