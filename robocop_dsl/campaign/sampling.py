"""Drawing the random conditions of one sample: where the moved bodies are and the
posture the robot starts from.

The draws depend on the campaign's seed, the sample number and the entry's place in
the file only: sample ``k`` sees the same conditions on every mission, world variant
and controller setting (so they can be compared pairwise), on any worker, in any order.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .spec import Normal, Uniform

_BODIES, _POSTURES = 0, 1


@dataclass(frozen=True)
class Conditions:
    """What a sample changes in a run.

    Attributes:
        body_placements: Body name -> 4x4 pose in the world [m].
        initial: Start configuration (size ``model.nq``), or ``None`` for the world's.
        parameters: Column name -> value, for the results table: ``BODY.x|y|z`` [m] and
            ``initial.JOINT`` [rad or m].
    """

    body_placements: dict = field(default_factory=dict)
    initial: np.ndarray | None = None
    parameters: dict = field(default_factory=dict)


def stream(seed: int, sample: int, kind: int, entry: int) -> np.random.Generator:
    """The random generator of one entry of one sample."""
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(sample, kind, entry)))


def draw(distribution: Uniform | Normal, rng: np.random.Generator, size: int,
         nominal: np.ndarray) -> np.ndarray:
    """One draw of ``size`` values; a :class:`Normal` without mean is centred on
    ``nominal``."""
    if isinstance(distribution, Uniform):
        low = np.broadcast_to(distribution.low, size)
        high = np.broadcast_to(distribution.high, size)
        return rng.uniform(low, high)
    mean = nominal if distribution.mean is None else np.broadcast_to(distribution.mean, size)
    return rng.normal(mean, np.broadcast_to(distribution.std, size))


def draw_conditions(job, world) -> Conditions:
    """The conditions of ``job``'s sample on ``world`` (the worker's copy of the variant)."""
    placements, parameters = {}, {}
    start = world.initial_configuration()
    for entry, move in enumerate(job.bodies):
        rng = stream(job.seed, job.sample, _BODIES, entry)
        poses = {body: world.body_pose(body, start).homogeneous for body in move.bodies}
        reference = poses[move.bodies[0]][:3, 3].copy()
        position = draw(move.position, rng, 3, reference)
        for body, pose in poses.items():
            moved = pose.copy()
            moved[:3, 3] = position + pose[:3, 3] - reference
            placements[body] = moved
            parameters.update({f"{body}.{axis}": float(value)
                               for axis, value in zip("xyz", moved[:3, 3])})
    if not job.postures:
        return Conditions(placements, None, parameters)
    initial = start.copy()
    for entry, noise in enumerate(job.postures):
        rng = stream(job.seed, job.sample, _POSTURES, entry)
        group = world.joint_group(noise.joints)
        indices = group.q_indices
        offset = draw(noise.distribution, rng, group.dofs, np.zeros(group.dofs))
        initial[indices] = np.clip(initial[indices] + offset, group.lower, group.upper)
        parameters.update({f"initial.{joint}": float(initial[index])
                           for joint, index in zip(group.joints, indices)})
    return Conditions(placements, initial, parameters)
