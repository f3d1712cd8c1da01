"""Running one job where it lands: in the sweeping process or in a worker process.

Each process keeps the worlds and missions it has built (:class:`WorkerCache`), so a
world variant is built and a mission parsed, checked and compiled once per worker,
never pickled; every run gets its own copy of the model from the runtime. Whatever
happens in a job (an exception, a run past its budget) becomes a row of the results
table, never an error of the campaign.
"""

from __future__ import annotations

import threading
import time
from collections import Counter
from dataclasses import dataclass

from ..world import load_world
from .probes import Budget, BudgetExceeded, Probe
from .sampling import Conditions, draw_conditions

GRACE = 10.0
"""Extra wall time [s] a job gets past its budget before it is abandoned, for a cycle
that never returns (the budget is otherwise enforced at every cycle)."""


class WorkerCache:
    """The worlds (by world file) and missions (by mission and world file) of a process.

    What a job varies never changes a cached world or mission: the settings, the moved
    bodies, the start posture and the physics go to the runner, which copies the model.
    So the world file (the variant) and the mission file are the whole key.

    Args:
        load_mission: ``load_mission(path, world=None)``; the runtime's by default.

    Attributes:
        built: How many times each kind (``world``, ``mission``) was built, since the
            cache was made or last cleared.
    """

    def __init__(self, load_mission=None):
        self._load_mission = load_mission
        self._lock = threading.RLock()
        self.worlds: dict = {}
        self.missions: dict = {}
        self.built: Counter = Counter()

    def world(self, path: str):
        """The world of ``path``, built (with its kinematic model) on first use."""
        with self._lock:
            if path not in self.worlds:
                world = load_world(path)
                world.model  # the kinematic model is built here, once per process
                self.worlds[path] = world
                self.built["world"] += 1
            return self.worlds[path]

    def mission(self, path: str, world_path: str):
        """The mission of ``path`` loaded on the world of ``world_path``."""
        with self._lock:
            key = (path, world_path)
            if key not in self.missions:
                load = self._load_mission
                if load is None:
                    from ..runtime import load_mission as load
                self.missions[key] = load(path, world=self.world(world_path))
                self.built["mission"] += 1
            return self.missions[key]

    def preload(self, pairs) -> None:
        """Build the missions of ``(mission path, world path)`` pairs and their worlds
        now; one that fails is left for its jobs, which record the error."""
        for mission, world in pairs:
            try:
                self.mission(mission, world)
            except Exception:
                continue

    def clear(self) -> None:
        """Forget every world and mission (their files may have changed)."""
        with self._lock:
            self.worlds.clear()
            self.missions.clear()
            self.built.clear()


PROCESS_CACHE = WorkerCache()


def reload_process_cache(loads) -> None:
    """Forget this process's worlds and missions, then load the ``(mission path, world
    path)`` pairs ``loads``: a long-lived worker, before a sweep."""
    PROCESS_CACHE.clear()
    PROCESS_CACHE.preload(loads)


@dataclass
class PreparedRun:
    """A job ready to run: its mission, a runner set up with its conditions."""

    mission: object
    runner: object
    conditions: Conditions


def prepare(job, cache: WorkerCache = PROCESS_CACHE) -> PreparedRun:
    """Build the runner of ``job``: its world variant, settings and sampled conditions."""
    world = cache.world(job.world)
    mission = cache.mission(job.mission, job.world)
    conditions = draw_conditions(job, world)
    runner = mission.runner(solver=job.setting("solver"), hierarchy=job.setting("hierarchy"),
                            time_step=job.setting("time_step"), initial=conditions.initial,
                            body_placements=conditions.body_placements or None,
                            physics=conditions.physics or None)
    return PreparedRun(mission, runner, conditions)


def job_row(job) -> dict:
    """The columns that identify a job, before it runs."""
    return {"job": job.index, "mission": job.mission_name,
            "mission_file": job.mission_file, "variant": job.variant,
            "sample": job.sample, "solver": job.setting("solver"),
            "hierarchy": job.setting("hierarchy"), "time_step": job.setting("time_step")}


def failed_row(job, error: Exception) -> dict:
    """The row of a job whose ``execute`` raised instead of returning a row."""
    return {**job_row(job), "outcome": "error", "message": f"{type(error).__name__}: {error}"}


def run_job(job, cache: WorkerCache = PROCESS_CACHE) -> dict:
    """Run ``job`` and return its row of the results table (see :mod:`.results`).

    A job with a budget runs in a thread of its own; one that has not returned
    :data:`GRACE` seconds after its budget is recorded as ``timeout`` and left behind.
    Ctrl-C meanwhile stops its run before ``KeyboardInterrupt`` goes on.
    """
    budget = Budget(job.time_budget, time.perf_counter())
    if job.time_budget is None:
        return _run(job, cache, budget)
    box: dict = {}
    thread = threading.Thread(target=lambda: box.update(row=_run(job, cache, budget)),
                              daemon=True, name=f"campaign-job-{job.index}")
    thread.start()
    try:
        thread.join(job.time_budget + GRACE)
    except KeyboardInterrupt:
        budget.expire()
        thread.join(GRACE)
        raise
    if "row" in box:
        return box["row"]
    return {**job_row(job), "outcome": "timeout", "wall_time": job.time_budget + GRACE,
            "message": f"did not return within {job.time_budget + GRACE:g} s; abandoned"}


def _run(job, cache: WorkerCache, budget: Budget) -> dict:
    started = time.perf_counter()
    row = job_row(job)
    probe, runner = Probe(), None
    try:
        prepared = prepare(job, cache)
        runner = prepared.runner
        row.update(prepared.conditions.parameters)
        _effective_settings(row, runner)
        runner.add_observer(probe)
        runner.add_observer(budget)
        budget.check()
        result = runner.run(duration=job.duration)
        row.update(outcome=result.outcome, final_state=result.final_state,
                   mission_time=result.mission_time, cycles=result.cycles,
                   qp_failures=result.qp_failures, message=result.message)
        if budget.exceeded is not None:
            row.update(outcome="timeout", message=str(budget.exceeded))
    except BudgetExceeded as error:
        row.update(outcome="timeout", message=str(error), **_progress(runner))
    except Exception as error:
        row.update(outcome="error", message=f"{type(error).__name__}: {error}",
                   **_progress(runner))
    row.update(probe.fields())
    row["wall_time"] = time.perf_counter() - started
    return row


def _progress(runner) -> dict:
    """Where an interrupted run was: its state, mission time [s] and cycles."""
    if runner is None:
        return {}
    return {"final_state": runner.state, "mission_time": runner.time, "cycles": runner.cycle}


def _effective_settings(row: dict, runner) -> None:
    """The controller settings the run uses, the world's where the campaign sets none."""
    controller = runner.controller
    row.update(solver=controller.solver, hierarchy=controller.hierarchy,
               time_step=controller.time_step)
