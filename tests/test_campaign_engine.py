"""Running real campaigns of missions/pickup.mission: the same table serially, on worker
processes of this machine and on a Dask scheduler and worker started as separate
processes; jobs that raise or time out are recorded while the others complete; worlds
are built once per process."""

import dataclasses
import functools
import json
import subprocess
import sys
import textwrap
import time

import pytest

from robocop_dsl.campaign import comparable, load_campaign, open_engine, read_results, \
    results_table, run_job, sweep
from robocop_dsl.campaign import worker as campaign_worker
from robocop_dsl.campaign.worker import WorkerCache
from robocop_dsl.cli.main import main

from conftest import MISSIONS

HOLD = """
mission hold "Keep the arms where they start for a long time."

world "bazar/sophia.yaml"
controller whole_body_controller

task arms: joint_position(bazar_arms) {
    interpolator = none
    feedback     = proportional(gain = 1)
}

state holding {
    enter {
        enable arms
        arms.target = current
    }
    when elapsed > 100 s -> done
}

final done
"""
MISSING_WORLD = "/nonexistent/robot.yaml"
POLLS = 600
"""How many times (every 0.1 s) to look for the Dask processes before giving up."""


def small_campaign(folder, missions, samples=3, extra=""):
    """A campaign file moving the part and adding start-posture noise."""
    text = f"""
        campaign: small
        missions: {missions}
        samples: {samples}
        seed: 5
        time_budget: 600 s
        vary:
          bodies:
            - move: [pickup_point, part_body]
              uniform: {{low: [0.65, 0.15, 0.76], high: [0.75, 0.25, 0.76]}}
          initial_posture:
            - joints: bazar_arms
              normal: {{std: 0.02}}
        """
    path = folder / "small.campaign.yaml"
    path.write_text(textwrap.dedent(text) + extra, encoding="utf-8")
    return path


def sweep_command(*argv):
    """``robocop-mission sweep ARGV...``; returns the exit code."""
    return main(["sweep", *map(str, argv)])


def execute_with_fault(job):
    """Job 1 names a world file missing where it runs, so the job raises."""
    if job.index == 1:
        job = dataclasses.replace(job, world=MISSING_WORLD)
    return run_job(job)


@pytest.fixture(scope="module")
def pickup_campaign(tmp_path_factory):
    return small_campaign(tmp_path_factory.mktemp("campaign"), [str(MISSIONS / "pickup.mission")])


@pytest.fixture(scope="module")
def serial_table(pickup_campaign, tmp_path_factory):
    output = tmp_path_factory.mktemp("serial") / "results.parquet"
    assert sweep_command(pickup_campaign, "--serial", "--output", output) == 0
    return read_results(output)


@pytest.fixture(scope="module")
def scheduler(tmp_path_factory):
    """A ``dask scheduler`` and a ``dask worker`` (2 threads) on 127.0.0.1, stopped after."""
    folder = tmp_path_factory.mktemp("dask")
    file = folder / "scheduler.json"
    dask = [sys.executable, "-m", "dask"]
    logs = open(folder / "dask.log", "w")
    processes = [subprocess.Popen(
        [*dask, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
         "--scheduler-file", str(file)], stdout=logs, stderr=logs)]
    try:
        address = json.loads(_wait_for(lambda: file.exists() and file.read_text())).get("address")
        processes.append(subprocess.Popen(
            [*dask, "worker", address, "--nworkers", "1", "--nthreads", "2", "--no-dashboard",
             "--host", "127.0.0.1"], stdout=logs, stderr=logs))
        from dask.distributed import Client

        with Client(address) as client:
            _wait_for(lambda: client.scheduler_info()["workers"])
        yield address
    finally:
        for process in reversed(processes):
            process.terminate()
            process.wait()
        logs.close()


def _wait_for(ready):
    for _ in range(POLLS):
        value = ready()
        if value:
            return value
        time.sleep(0.1)
    raise RuntimeError("the Dask processes did not start")


def test_serial_campaign_runs_the_real_mission(serial_table):
    """Every job of the small campaign ran the pickup mission to its end."""
    rows = serial_table.to_pylist()
    assert [(r["job"], r["mission"], r["variant"], r["sample"]) for r in rows] == [
        (0, "pickup", "sophia", 0), (1, "pickup", "sophia", 1), (2, "pickup", "sophia", 2)]
    assert {r["mission_file"] for r in rows} == {str(MISSIONS / "pickup.mission")}
    assert {r["outcome"] for r in rows} == {"success"}
    assert all(r["final_state"] == "done" and r["cycles"] > 100 for r in rows)
    assert all(0 <= r["min_limit_margin"] < 3 and r["limit_joint"] for r in rows)
    assert all(r["solver"] == "auto" and r["time_step"] == 0.005 for r in rows)
    assert len({r["pickup_point.x"] for r in rows}) == 3


def test_local_workers_give_the_same_table(serial_table, pickup_campaign, tmp_path):
    """Two worker processes of this machine produce the serial table, wall times aside."""
    output = tmp_path / "local.parquet"
    assert sweep_command(pickup_campaign, "--workers", 2, "--output", output) == 0
    assert comparable(read_results(output)).equals(comparable(serial_table))


def test_scheduler_and_worker_processes_give_the_same_table(serial_table, pickup_campaign,
                                                             scheduler, tmp_path):
    """A scheduler and a worker started with the dask command produce the serial table."""
    output = tmp_path / "remote.parquet"
    assert sweep_command(pickup_campaign, "--scheduler", scheduler, "--output", output) == 0
    assert comparable(read_results(output)).equals(comparable(serial_table))


@pytest.mark.parametrize("where", [{"serial": True}, {"workers": 2}])
def test_raising_and_overrunning_jobs_are_recorded(tmp_path, where):
    """A job that raises and jobs past their budget are rows; the other jobs complete."""
    hold = tmp_path / "hold.mission"
    hold.write_text(HOLD, encoding="utf-8")
    missions = [str(MISSIONS / "pickup.mission"), {"path": str(hold), "time_budget": "0.2 s"}]
    campaign = load_campaign(small_campaign(tmp_path, json.dumps(missions), samples=2))
    with open_engine(**where) as engine:
        rows, interrupted = sweep(campaign, engine, execute=execute_with_fault)
    rows = results_table(rows).to_pylist()
    assert not interrupted
    assert [(r["mission"], r["outcome"]) for r in rows] == [
        ("pickup", "success"), ("pickup", "error"), ("hold", "timeout"), ("hold", "timeout")]
    assert MISSING_WORLD in rows[1]["message"]
    assert all("time budget of 0.2 s" in r["message"] for r in rows[2:])
    assert all(r["final_state"] == "holding" and r["mission_time"] < 100 for r in rows[2:])


def test_worlds_and_missions_are_built_once_per_process(tmp_path, monkeypatch):
    """Two variants, three samples each: each world and mission is loaded once."""
    variant = tmp_path / "other_start.yaml"
    variant.write_text(textwrap.dedent("""
        models:
          - include: bazar/workcell.yaml
          - path: bazar/models/kinect2.urdf
            namespace: kinect2
            joint: {parent: bazar_ptu_mount_link}
        initial:
          bazar_arms: [0, 0.25, 0, -2, 0, 0.7, 0, 0, 0.25, 0, -2, 0, 0.7, 0]
        processors:
          whole_body_controller:
            type: qp_controller
            options: {joint_group: bazar_upper_joints, time_step: 5ms, solver: proxqp,
                      hierarchy: strict}
          driver:
            type: simulated
            options: {joint_group: bazar_upper_joints}
        """), encoding="utf-8")
    variants = f"variants: {{sophia: bazar/sophia.yaml, other_start: {variant}}}"
    campaign = load_campaign(small_campaign(tmp_path, [str(MISSIONS / "pickup.mission")],
                                            extra=f"{variants}\nduration: 0.5 s\n"))
    loads = []
    real_load = campaign_worker.load_world
    monkeypatch.setattr(campaign_worker, "load_world", lambda p: loads.append(p) or real_load(p))
    cache = WorkerCache()
    with open_engine(serial=True) as engine:
        rows, _ = sweep(campaign, engine, execute=functools.partial(run_job, cache=cache))
    assert sorted(loads) == sorted({job.world for job in campaign.jobs})
    assert len(cache.missions) == 2
    assert [r["variant"] for r in results_table(rows).to_pylist()] == ["sophia"] * 3 + [
        "other_start"] * 3
    assert {r["outcome"] for r in rows} == {"stopped"}
