"""What a campaign file says, as frozen data: missions, world variants, controller
settings and the conditions drawn at random for every sample.

Everything here is small and picklable: jobs carry these objects to the workers, which
build worlds and draw conditions themselves. Lengths are metres, angles radians and
durations seconds.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ..diagnostics import SourceFile, Span

SETTINGS = ("solver", "hierarchy", "time_step")


@dataclass(frozen=True)
class Where:
    """The place in the campaign file a value was written, for later diagnostics."""

    source: SourceFile
    span: Span

    def error(self, code: str, message: str, hint: str | None = None):
        return self.source.error(code, message, self.span, hint)


@dataclass(frozen=True)
class Uniform:
    """Uniform in the box ``[low, high]`` (per coordinate)."""

    low: tuple
    high: tuple

    def __repr__(self) -> str:
        return f"uniform(low={list(self.low)}, high={list(self.high)})"


@dataclass(frozen=True)
class Normal:
    """Normal with standard deviation ``std`` around ``mean`` (``None``: the nominal
    value, that is the body's position in the world or the world's initial posture)."""

    std: tuple
    mean: tuple | None = None

    def __repr__(self) -> str:
        return f"normal(mean={self.mean and list(self.mean)}, std={list(self.std)})"


@dataclass(frozen=True)
class BodyMove:
    """Bodies fixed to the world that move together: the first one's position [m] is
    drawn from ``position``; the others keep their offsets to it, and every body keeps
    its orientation."""

    bodies: tuple
    position: Uniform | Normal
    where: Where | None = field(compare=False, repr=False)
    body_spans: tuple = field(default=(), compare=False, repr=False)


@dataclass(frozen=True)
class PostureNoise:
    """Noise added to the start posture of ``joints`` (a joint group or a joint) around
    the world's initial posture, then clipped to the joint limits.

    ``distribution`` is a :class:`Normal` (``std`` [rad or m]) or a :class:`Uniform`
    (offsets ``low``..``high`` [rad or m]); one value is broadcast over the dofs.
    """

    joints: str
    distribution: Uniform | Normal
    where: Where | None = field(compare=False, repr=False)


@dataclass(frozen=True)
class PhysicsNoise:
    """Physics drawn per sample: the sliding ``friction`` coefficient of every contact
    [-] and the ``masses`` [kg] of free bodies, ``(body, distribution)`` pairs; each
    a :class:`Uniform` or :class:`Normal` (a normal without mean is centred on the
    world's value), or absent."""

    friction: Uniform | Normal | None = None
    masses: tuple = ()
    where: Where | None = field(default=None, compare=False, repr=False)
    mass_spans: tuple = field(default=(), compare=False, repr=False)

    def __bool__(self) -> bool:
        return self.friction is not None or bool(self.masses)


@dataclass(frozen=True)
class MissionEntry:
    """A mission file to run, with its own ``duration`` and ``time_budget`` [s] when
    they differ from the campaign's."""

    path: Path
    where: Where = field(compare=False, repr=False)
    duration: float | None = None
    time_budget: float | None = None


@dataclass(frozen=True)
class VariantEntry:
    """A named world variant: a world file every mission is run on instead of its own."""

    name: str
    world: str
    where: Where = field(compare=False, repr=False)


@dataclass(frozen=True)
class CampaignSpec:
    """A campaign file, read and checked for shape but not yet against any world.

    ``settings`` maps ``solver``, ``hierarchy`` and ``time_step`` [s] to the tuple of
    values to try (every combination is run); an absent setting keeps the world's.
    ``settings_where`` locates each written value.
    """

    name: str
    path: Path
    description: str
    missions: tuple
    variants: tuple
    settings: dict
    samples: int
    seed: int
    duration: float | None
    time_budget: float | None
    bodies: tuple
    postures: tuple
    physics: PhysicsNoise = PhysicsNoise()
    settings_where: dict = field(default_factory=dict, compare=False, repr=False)

    @property
    def folder(self) -> Path:
        return self.path.parent
