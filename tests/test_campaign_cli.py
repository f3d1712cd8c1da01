"""``robocop-mission sweep``: exit codes, located errors, the summary and rerunning a job
alone with the printed command."""

import contextlib
import io
import json
import shlex
import textwrap

import pytest

from robocop_dsl.campaign import read_results
from robocop_dsl.campaign.rerun import campaign_job
from robocop_dsl.cli.main import main
from robocop_dsl.diagnostics import DiagnosticError

from conftest import MISSIONS
from test_campaign_engine import HOLD, small_campaign, sweep_command

PICKUP = MISSIONS / "pickup.mission"


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    """A serial sweep where the pickup jobs succeed and the hold jobs overrun their budget."""
    folder = tmp_path_factory.mktemp("swept")
    (folder / "hold.mission").write_text(HOLD, encoding="utf-8")
    missions = [str(PICKUP), {"path": "hold.mission", "time_budget": "0.3 s"}]
    path = small_campaign(folder, json.dumps(missions), samples=2)
    output = folder / "results.parquet"
    with contextlib.redirect_stdout(io.StringIO()) as out:
        code = sweep_command(path, "--serial", "--output", output)
    return path, output, folder, code, out.getvalue()


def test_sweep_writes_the_table_and_the_summary(swept):
    """Exit 1 when a job fails; the summary gives rates, failures and rerun commands."""
    path, output, folder, code, out = swept
    assert code == 1
    rows = read_results(output).to_pylist()
    assert [(r["job"], r["mission"], r["outcome"]) for r in rows] == [
        (0, "pickup", "success"), (1, "pickup", "success"),
        (2, "hold", "timeout"), (3, "hold", "timeout")]
    assert "small: 4 jobs on serial, in this process" in out
    assert "2 jobs did not succeed" in out
    assert "job 2: hold on sophia, sample 0: timeout in state holding" in out
    commands = [line.split("rerun: ")[1] for line in out.splitlines() if "rerun: " in line]
    assert [shlex.split(c)[-4:] for c in commands] == [
        ["--campaign", str(path), "--job", "2"], ["--campaign", str(path), "--job", "3"]]
    assert shlex.split(commands[0])[:3] == ["robocop-mission", "run", str(folder / "hold.mission")]


def test_rerun_reproduces_the_job(swept):
    """The job a rerun command names runs as it did in the sweep: same conditions, same end."""
    path, output = swept[:2]
    row = read_results(output).to_pylist()[1]
    job, prepared = campaign_job(path, 1, PICKUP)
    assert (job.index, job.sample) == (1, 1)
    assert prepared.conditions.parameters["pickup_point.x"] == row["pickup_point.x"]
    result = prepared.runner.run(duration=job.duration)
    assert (result.outcome, result.final_state, result.cycles, result.mission_time) == (
        row["outcome"], row["final_state"], row["cycles"], row["mission_time"])


def test_printed_command_reruns_the_job(swept, capsys):
    """The rerun command the summary prints works as typed (run --campaign --job)."""
    path, output = swept[:2]
    row = read_results(output).to_pylist()[1]
    assert main(["run", str(PICKUP), "--campaign", str(path), "--job", "1"]) == 0
    out = capsys.readouterr().out
    assert f"mission time: {row['mission_time']:.3f} s" in out
    assert main(["run", str(PICKUP), "--job", "1"]) == 2
    assert "--campaign and --job go together" in capsys.readouterr().err


def test_rerun_refuses_another_mission_or_job(swept):
    """A job number out of range, or a job that runs another mission, is refused."""
    path = swept[0]
    with pytest.raises(DiagnosticError, match="jobs 0 to 3, not 9"):
        campaign_job(path, 9, PICKUP)
    with pytest.raises(DiagnosticError, match="job 2 runs .*hold.mission"):
        campaign_job(path, 2, PICKUP)


def test_malformed_campaign_is_a_located_error(tmp_path, capsys):
    """Exit 2 and a gcc-style diagnostic; nothing runs and no table is written."""
    path = tmp_path / "bad.campaign.yaml"
    path.write_text(textwrap.dedent(f"""
        missions: [{PICKUP}]
        vary:
          bodies:
            - move: pickup_pont
              uniform: {{low: [0.6, 0.1, 0.76], high: [0.8, 0.3, 0.76]}}
        """).lstrip(), encoding="utf-8")
    output = tmp_path / "results.parquet"
    assert sweep_command(path, "--serial", "--output", output) == 2
    err = capsys.readouterr().err.splitlines()
    assert err[:4] == [
        f"{path}:4:13: error[unknown-body]: unknown body 'pickup_pont'",
        " 4 |     - move: pickup_pont",
        "   |             ^^^^^^^^^^^",
        "   = hint: did you mean 'pickup_point'?",
    ]
    assert not output.exists()


def test_invalid_mission_stops_before_anything_runs(tmp_path, capsys):
    """A mission with an error: its diagnostics, exit 2, no table."""
    broken = tmp_path / "broken.mission"
    broken.write_text(PICKUP.read_text().replace("-> grasp", "-> grab"), encoding="utf-8")
    path = small_campaign(tmp_path, [str(broken)])
    output = tmp_path / "results.parquet"
    assert sweep_command(path, "--serial", "--output", output, "--format", "github") == 2
    err = capsys.readouterr().err
    assert err.startswith(f"::error file={broken},") and "grab" in err
    assert not output.exists()
