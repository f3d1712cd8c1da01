"""``sweep`` on hostile input and signals: SIGTERM and Ctrl-C stop the workers and write
the finished jobs; an output that cannot be written or must not be overwritten is
refused before anything runs; malformed campaigns, names, numbers and scheduler
addresses are clean errors (exit 2, no traceback); names print literally; the workers
never outnumber the CPUs. Tests wait for conditions (a progress line, processes
gone), never for the clock."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import psutil
import pytest

from robocop_dsl.campaign import read_results
from robocop_dsl.cli.main import main
from robocop_dsl.cli.sweep_cmd import cpu_count

from conftest import MISSIONS, REPO
from test_campaign_engine import HOLD

PICKUP = MISSIONS / "pickup.mission"
GIVE_UP = 120.0
"""Wall time [s] after which a process still there counts as left behind for good."""


def campaign(folder, text: str = "", name: str = "tiny"):
    """``folder/tiny.campaign.yaml``: one pickup job capped at 1 s, and ``text``."""
    path = folder / "tiny.campaign.yaml"
    path.write_text(f"campaign: {json.dumps(name)}\nmissions:\n  - {{path: {PICKUP}, duration: 1 s}}\n"
                    + text, encoding="utf-8")
    return path


def sweep(capsys, *argv) -> tuple:
    """``robocop-mission sweep ARGV``: exit code, stdout, stderr."""
    code = main(["sweep", *map(str, argv)])
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return code, out, err


# ---- signals -----------------------------------------------------------------------

@pytest.mark.parametrize("number, options, extra, code", [
    (signal.SIGTERM, ["--workers", "2"], "", 143),
    (signal.SIGINT, ["--serial"], "", 130),
    (signal.SIGINT, ["--serial"], "time_budget: 600 s\n", 130),
], ids=["sigterm-workers", "ctrl-c-serial", "ctrl-c-serial-budget"])
def test_a_signal_stops_the_sweep_and_writes_the_finished_jobs(tmp_path, number, options,
                                                               extra, code):
    """After the first job, the signal stops the sweep: the finished job is written,
    the other jobs (long holds) are not run, no process is left, nothing on stderr
    but progress."""
    (tmp_path / "hold.mission").write_text(HOLD, encoding="utf-8")
    hold = tmp_path / "hold.mission"
    path = campaign(tmp_path, f"  - {hold}\n  - {hold}\n{extra}")
    output, out, err = (tmp_path / name for name in ("results.parquet", "out", "err"))
    with out.open("w") as stdout, err.open("w") as stderr:
        process = subprocess.Popen(
            [sys.executable, "-m", "robocop_dsl", "sweep", str(path), "-o", str(output),
             *options], cwd=REPO, stdout=stdout, stderr=stderr)
    while "1/3 jobs" not in err.read_text():
        assert process.poll() is None, err.read_text()
        time.sleep(0.05)
    children = psutil.Process(process.pid).children(recursive=True)
    process.send_signal(number)
    assert process.wait() == code, err.read_text()
    assert err.read_text().startswith("1/3 jobs") and len(err.read_text().splitlines()) == 1
    assert "1 of 3 jobs" in out.read_text()
    assert [(r["job"], r["outcome"]) for r in read_results(output).to_pylist()] == [
        (0, "stopped")]
    _, alive = psutil.wait_procs(children, timeout=GIVE_UP)
    for process in alive:
        process.kill()
    assert not alive


# ---- the output ----------------------------------------------------------------------

@pytest.mark.parametrize("output, message", [
    ("folder", "cannot write the results to '{tmp}/folder': it is a folder"),
    ("/proc/version", "cannot write the results to '/proc/version': the file exists and "
                      "is not a results table: give --replace to write over it"),
    ("/sys/x.parquet", "cannot write the results to '/sys/x.parquet': "),
    ("file/sub.parquet", "cannot write the results to '{tmp}/file/sub.parquet': "
                         "'{tmp}/file' is not a folder"),
    ("pickup.mission", "cannot write the results to '{tmp}/pickup.mission': the file "
                       "exists and is not a results table: give --replace to write over it"),
    ("", "--output needs a file name, e.g. results.parquet"),
])
def test_an_output_that_cannot_be_written_is_refused_before_anything_runs(
        tmp_path, capsys, output, message):
    """Exit 2 and one line, before a job runs; the file there is left as it was."""
    if output.startswith("/") and not os.path.exists(os.path.dirname(output)):
        pytest.skip(f"no {os.path.dirname(output)} here")
    (tmp_path / "folder").mkdir()
    (tmp_path / "file").write_text("kept\n")
    (tmp_path / "pickup.mission").write_bytes(PICKUP.read_bytes())
    target = output if output.startswith("/") or not output else tmp_path / output
    code, out, err = sweep(capsys, campaign(tmp_path), "--serial", "-o", target)
    assert code == 2 and out == ""
    assert err.startswith("error: " + message.format(tmp=tmp_path))
    assert len(err.splitlines()) == 1
    assert (tmp_path / "pickup.mission").read_bytes() == PICKUP.read_bytes()


def test_a_results_table_is_replaced_and_another_file_only_with_replace(tmp_path, capsys):
    """A second sweep to the same table replaces it; --replace writes over any file."""
    path, output = campaign(tmp_path), tmp_path / "results.parquet"
    for _ in range(2):
        assert sweep(capsys, path, "--serial", "-o", output)[0] == 1  # the job is stopped
        assert read_results(output).num_rows == 1
    other = tmp_path / "notes.txt"
    other.write_text("notes\n")
    assert sweep(capsys, path, "--serial", "-o", other)[0] == 2
    assert other.read_text() == "notes\n"
    assert sweep(capsys, path, "--serial", "-o", other, "--replace")[0] == 1
    assert read_results(other).num_rows == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "notes.txt", "results.parquet", "tiny.campaign.yaml"]


# ---- the campaign file ---------------------------------------------------------------

@pytest.mark.parametrize("name", ['"../../x/evil"', '"a\\0b"', '".."', '"a\\\\b"'])
def test_a_campaign_name_that_cannot_name_a_file_is_located(tmp_path, capsys, name):
    """The name names the default results file: a path, NUL or '..' is refused."""
    path = tmp_path / "bad.campaign.yaml"
    path.write_text(f"campaign: {name}\nmissions: [{PICKUP}]\n", encoding="utf-8")
    code, out, err = sweep(capsys, path, "--serial")
    assert code == 2 and out == ""
    assert err.startswith(f"{path}:1:11: error[wrong-value]: campaign name ")
    assert "cannot name a file" in err.splitlines()[0]
    assert list(tmp_path.iterdir()) == [path]


@pytest.mark.parametrize("text, message", [
    ("missions: 5\n", "2:11: error[wrong-value]: 'missions' must be a list"),
    ("missions: [a.mission]\nvariants: 3\n",
     "3:11: error[wrong-value]: 'variants' must be a mapping"),
])
def test_missions_and_variants_of_the_wrong_kind_are_located(tmp_path, capsys, text, message):
    path = tmp_path / "bad.campaign.yaml"
    path.write_text("campaign: bad\n" + text, encoding="utf-8")
    code, out, err = sweep(capsys, path, "--serial")
    assert code == 2 and f"{path}:{message}" in err


@pytest.mark.parametrize("text, where", [
    ("settings: {time_step: .nan}\n", "4:23: error[wrong-value]: 'time_step' must be finite"),
    ("settings: {time_step: [5ms, .inf]}\n",
     "4:29: error[wrong-value]: 'time_step' must be finite"),
    ("vary:\n  bodies:\n    - move: pickup_point\n"
     "      uniform: {low: [.nan, 0, 0.76], high: [1, 1, 0.76]}\n",
     "7:22: error[wrong-value]: 'low' must be finite"),
    ("vary:\n  initial_posture:\n    - joints: bazar_arms\n"
     "      uniform: {low: .nan, high: .nan}\n",
     "7:22: error[wrong-value]: 'low' must be finite"),
    ("vary:\n  initial_posture:\n    - joints: bazar_arms\n      normal: {std: .inf}\n",
     "7:21: error[wrong-value]: 'std' must be finite"),
    ("vary:\n  physics:\n    friction: {normal: {std: 0.1, mean: .inf}}\n",
     "6:41: error[wrong-value]: 'mean' must be finite"),
])
def test_numbers_that_are_not_finite_are_located(tmp_path, capsys, text, where):
    """NaN and infinity are refused where they are written, before anything runs."""
    path = campaign(tmp_path, text)
    code, out, err = sweep(capsys, path, "--serial")
    assert code == 2 and out == ""
    assert f"{path}:{where}" in err


def test_names_print_literally(tmp_path, capsys):
    """Rich markup in the campaign's and variants' names is printed as written."""
    path = campaign(tmp_path, 'variants: {"[/]": bazar/sophia.yaml, '
                              '"[red]y": bazar/sophia.yaml}\n', name="[red]x")
    code, out, err = sweep(capsys, path, "--serial", "-o", tmp_path / "results.parquet")
    assert code == 1
    assert out.startswith("[red]x: 2 jobs on serial, in this process\n")
    assert "job 0: pickup on [/], sample 0: stopped" in out
    assert "job 1: pickup on [red]y, sample 0: stopped" in out
    assert [r["variant"] for r in read_results(tmp_path / "results.parquet").to_pylist()] == [
        "[/]", "[red]y"]


# ---- where the jobs run --------------------------------------------------------------

@pytest.mark.parametrize("address, message", [
    ("garbage", "cannot reach the Dask scheduler: missing port number"),
    ("foo://bar", "cannot reach the Dask scheduler: unknown address scheme 'foo'"),
    ("tcp://[::1", "cannot reach the Dask scheduler: invalid address '[::1'"),
    ("", "--scheduler needs an address, e.g. tcp://10.0.0.5:8786"),
])
def test_a_scheduler_address_that_does_not_parse_is_a_clean_error(tmp_path, capsys,
                                                                  address, message):
    output = tmp_path / "results.parquet"
    code, out, err = sweep(capsys, campaign(tmp_path), "--scheduler", address, "-o", output)
    assert code == 2 and out == ""
    assert err.startswith(f"error: {message}") and len(err.splitlines()) == 1
    assert not output.exists()


def test_workers_never_outnumber_the_cpus(tmp_path, capsys):
    """--workers above the CPUs this process may use starts one per CPU (and never
    more than jobs); --help says so."""
    path = campaign(tmp_path, f"  - {{path: {PICKUP}, duration: 1 s}}\n"
                              f"  - {{path: {PICKUP}, duration: 1 s}}\n")
    code, out, _ = sweep(capsys, path, "--workers", "64", "-o", tmp_path / "results.parquet")
    assert code == 1
    assert out.startswith(f"tiny: 3 jobs on {min(cpu_count(), 3)} worker processes")
    assert main(["sweep", "--help"]) == 0
    assert "never more than the CPUs" in " ".join(capsys.readouterr().out.split())

