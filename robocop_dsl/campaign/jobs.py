"""Jobs: one run of one mission, on one world variant, with one combination of
controller settings and one sample of the random conditions.

A job is small, frozen and picklable: paths and numbers, never a world. Its index is
its place in the expansion order (missions, then variants, then settings, then
samples), so the same campaign file always gives the same jobs. Jobs carry the
campaign's entries without their places in the file.
"""

from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass
from pathlib import Path

from .reader import read_campaign
from .spec import SETTINGS, CampaignSpec, PhysicsNoise


@dataclass(frozen=True)
class Job:
    """One run to make.

    Attributes:
        index: Place in the campaign, from 0.
        mission: Absolute path of the ``.mission`` file.
        mission_name: The name the mission declares.
        mission_file: The mission file's path as the campaign names it.
        variant: The world variant's name.
        world: Absolute path of the variant's world file.
        sample: Which sample of the random conditions, from 0.
        settings: ``(name, value)`` pairs overriding the controller's ``solver``,
            ``hierarchy`` and ``time_step`` [s].
        seed: The campaign's seed.
        duration: Mission-time cap [s], or ``None``.
        time_budget: Wall-time budget [s], or ``None``.
        bodies: The :class:`~.spec.BodyMove` entries.
        postures: The :class:`~.spec.PostureNoise` entries.
        physics: The :class:`~.spec.PhysicsNoise`.
    """

    index: int
    mission: str
    mission_name: str
    mission_file: str
    variant: str
    world: str
    sample: int
    settings: tuple
    seed: int
    duration: float | None
    time_budget: float | None
    bodies: tuple
    postures: tuple
    physics: PhysicsNoise = PhysicsNoise()

    def setting(self, name: str):
        """The value of a controller setting, or ``None`` when the world's applies."""
        return dict(self.settings).get(name)


@dataclass(frozen=True)
class Campaign:
    """A checked campaign and its jobs."""

    spec: CampaignSpec
    jobs: tuple

    @property
    def name(self) -> str:
        return self.spec.name

    @property
    def path(self) -> Path:
        return self.spec.path

    @property
    def loads(self) -> tuple:
        """The ``(mission path, world path)`` pairs its jobs run, each once, in job order:
        what a worker loads before running them."""
        return tuple(dict.fromkeys((job.mission, job.world) for job in self.jobs))


def load_campaign(path: str | Path, load_mission=None) -> Campaign:
    """Read a campaign file, check it with all its missions and expand it into jobs.

    Args:
        path: The campaign file.
        load_mission: ``load_mission(path, world=None)``; the runtime's by default.

    Raises:
        DiagnosticError: every problem in the campaign file and in its missions.
    """
    from .checker import check_campaign

    spec = read_campaign(path)
    pairings = check_campaign(spec, load_mission)
    return Campaign(spec, tuple(expand(spec, pairings)))


def setting_combinations(spec: CampaignSpec) -> list:
    """Every combination of the listed settings, as tuples of ``(name, value)``."""
    names = [name for name in SETTINGS if name in spec.settings]
    values = [spec.settings[name] for name in names]
    return [tuple(zip(names, combination)) for combination in itertools.product(*values)]


def expand(spec: CampaignSpec, pairings) -> list:
    """The jobs of a campaign, numbered in expansion order."""
    jobs = []
    bodies = tuple(dataclasses.replace(m, where=None, body_spans=()) for m in spec.bodies)
    postures = tuple(dataclasses.replace(p, where=None) for p in spec.postures)
    physics = dataclasses.replace(spec.physics, where=None, mass_spans=())
    for pairing in pairings:
        entry = pairing.entry
        for settings in setting_combinations(spec):
            for sample in range(spec.samples):
                jobs.append(Job(
                    index=len(jobs), mission=pairing.mission, mission_name=pairing.mission_name,
                    mission_file=entry.path.as_posix(),
                    variant=pairing.variant, world=pairing.world, sample=sample,
                    settings=settings, seed=spec.seed,
                    duration=entry.duration if entry.duration is not None else spec.duration,
                    time_budget=(entry.time_budget if entry.time_budget is not None
                                 else spec.time_budget),
                    bodies=bodies, postures=postures, physics=physics))
    return jobs
