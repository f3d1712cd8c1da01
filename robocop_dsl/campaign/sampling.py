"""Drawing the random conditions of one sample: where the moved bodies are, the
posture the robot starts from and the physics (friction, free bodies' masses).

The draws depend on the campaign's seed, the sample number and the entry's place in
the file only: sample ``k`` sees the same conditions on every mission, world variant
and controller setting (so they can be compared pairwise), on any worker, in any order.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .spec import Normal, Uniform

_BODIES, _POSTURES, _PHYSICS = 0, 1, 2
SMALLEST = 1e-6
"""A drawn friction coefficient [-] or mass [kg] is at least this (a normal may draw
below zero)."""


@dataclass(frozen=True)
class Conditions:
    """What a sample changes in a run.

    Attributes:
        body_placements: Body name -> 4x4 pose in the world [m], for bodies fixed to it.
        initial: Start configuration (size ``model.nq``), or ``None`` for the world's: a
            free body moved starts there.
        physics: ``friction`` [-] and ``mass`` (free body -> kg) for a physics driver.
        parameters: Column name -> value, for the results table: ``BODY.x|y|z`` [m],
            ``initial.JOINT`` [rad or m], ``physics.friction`` [-], ``BODY.mass`` [kg].
    """

    body_placements: dict = field(default_factory=dict)
    initial: np.ndarray | None = None
    parameters: dict = field(default_factory=dict)
    physics: dict = field(default_factory=dict)


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
    initial = start.copy()
    free = set(world.free_bodies())
    for entry, move in enumerate(job.bodies):
        rng = stream(job.seed, job.sample, _BODIES, entry)
        poses = {body: world.body_pose(body, start).homogeneous for body in move.bodies}
        reference = poses[move.bodies[0]][:3, 3].copy()
        position = draw(move.position, rng, 3, reference)
        for body, pose in poses.items():
            moved = pose.copy()
            moved[:3, 3] = position + pose[:3, 3] - reference
            if body in free:
                world.place_free(initial, body, moved)
            else:
                placements[body] = moved
            parameters.update({f"{body}.{axis}": float(value)
                               for axis, value in zip("xyz", moved[:3, 3])})
    for entry, noise in enumerate(job.postures):
        rng = stream(job.seed, job.sample, _POSTURES, entry)
        group = world.joint_group(noise.joints)
        indices = group.q_indices
        offset = draw(noise.distribution, rng, group.dofs, np.zeros(group.dofs))
        initial[indices] = np.clip(initial[indices] + offset, group.lower, group.upper)
        parameters.update({f"initial.{joint}": float(initial[index])
                           for joint, index in zip(group.joints, indices)})
    physics = _draw_physics(job, world, parameters)
    changed = bool(job.postures) or any(b in free for move in job.bodies for b in move.bodies)
    return Conditions(placements, initial if changed else None, parameters, physics)


def _draw_physics(job, world, parameters: dict) -> dict:
    """The sample's friction and masses (each entry its own stream)."""
    noise = getattr(job, "physics", None)
    if not noise:
        return {}
    physics: dict = {}
    if noise.friction is not None:
        rng = stream(job.seed, job.sample, _PHYSICS, 0)
        nominal = np.array([world.physics.friction[0]])
        physics["friction"] = max(float(draw(noise.friction, rng, 1, nominal)[0]), SMALLEST)
        parameters["physics.friction"] = physics["friction"]
    for entry, (body, distribution) in enumerate(noise.masses, start=1):
        rng = stream(job.seed, job.sample, _PHYSICS, entry)
        nominal = np.array([free_mass(world, body)])
        mass = max(float(draw(distribution, rng, 1, nominal)[0]), SMALLEST)
        physics.setdefault("mass", {})[body] = mass
        parameters[f"{body}.mass"] = mass
    return physics


def free_mass(world, body: str) -> float:
    """The mass [kg] physics gives free ``body`` (its URDF ``<inertial>``)."""
    model = world.model
    return float(model.inertias[model.frames[world.body_frame_id(body)].parentJoint].mass)
