"""Running one job of a campaign alone (``robocop-mission run MISSION --campaign FILE
--job N``): the same world variant, settings and sampled conditions as in the sweep,
with everything ``run`` offers around it (progress, log, viewer, real time)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from ..diagnostics import Diagnostic, DiagnosticError
from .jobs import load_campaign
from .worker import PreparedRun, WorkerCache, prepare


def campaign_job(campaign_path: str | Path, index: int, mission_path: str | Path,
                 solver: str | None = None, hierarchy: str | None = None):
    """The job ``index`` of a campaign, ready to run.

    Args:
        campaign_path: The campaign file.
        index: The job's number (the ``job`` column of the results table).
        mission_path: The mission file the user named; it must be the job's.
        solver: Overrides the job's QP solver when given.
        hierarchy: Overrides the job's hierarchy when given.

    Returns:
        ``(job, prepared)``: the :class:`~.jobs.Job` and its :class:`PreparedRun`.

    Raises:
        DiagnosticError: an invalid campaign or mission, a job number out of range, or
            a job that runs another mission.
    """
    campaign = load_campaign(campaign_path)
    if not 0 <= index < len(campaign.jobs):
        raise DiagnosticError([Diagnostic(
            "unknown-job", f"the campaign has jobs 0 to {len(campaign.jobs) - 1}, not {index}",
            str(campaign_path), None)])
    job = campaign.jobs[index]
    if Path(mission_path).resolve() != Path(job.mission):
        raise DiagnosticError([Diagnostic(
            "wrong-mission", f"job {index} runs {job.mission}, not {mission_path}",
            str(campaign_path), None, hint=f"run {job.mission} instead")])
    overrides = {"solver": solver, "hierarchy": hierarchy}
    settings = dict(job.settings)
    settings.update({name: value for name, value in overrides.items() if value is not None})
    job = dataclasses.replace(job, settings=tuple(settings.items()))
    prepared: PreparedRun = prepare(job, WorkerCache())
    return job, prepared
