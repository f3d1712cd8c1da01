"""Checking a campaign against its missions and worlds before anything runs.

Every mission is loaded (parsed and checked) once on every world it will run on; the
bodies, joints and solvers the campaign names are looked up in those worlds. All the
problems are reported together: the campaign's located in the campaign file, the
missions' in the mission files.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..diagnostics import DiagnosticError, did_you_mean, sort_key, unique
from ..world import load_world
from .spec import CampaignSpec, MissionEntry, VariantEntry

ROOT = "world"


@dataclass(frozen=True)
class Pairing:
    """One mission on one world variant; paths are absolute."""

    mission: str
    mission_name: str
    variant: str
    world: str
    entry: MissionEntry


def check_campaign(spec: CampaignSpec, load_mission=None) -> tuple:
    """Load every mission on every world it runs on and check the campaign's names.

    Args:
        spec: The campaign as read.
        load_mission: ``load_mission(path, world=None)``; the runtime's by default.

    Returns:
        The :class:`Pairing` of each mission with each world variant, in file order.

    Raises:
        DiagnosticError: every problem found, in the campaign and in the missions.
    """
    if load_mission is None:
        from ..runtime import load_mission
    checker = _Checker(spec, load_mission)
    pairings = checker.pairings()
    checker.names()
    if checker.diagnostics:
        raise DiagnosticError(sorted(unique(checker.diagnostics), key=sort_key))
    return tuple(pairings)


class _Checker:
    def __init__(self, spec: CampaignSpec, load_mission):
        self.spec = spec
        self.load_mission = load_mission
        self.diagnostics: list = []
        self.worlds: dict = {}

    def pairings(self) -> list:
        variants = [(v, self.variant_world(v)) for v in self.spec.variants]
        result = []
        for entry in self.spec.missions:
            path = self.mission_path(entry)
            if path is None:
                continue
            if not self.spec.variants:
                mission = self.load(path, None)
                if mission is not None:
                    world = mission.world
                    self.worlds.setdefault(_stem(world.path), world)
                    result.append(Pairing(str(path), mission.name, _stem(world.path),
                                          str(Path(world.path).resolve()), entry))
            failed: dict = {}
            for variant, world in variants:
                mission = self.load(path, world, failed, variant) if world is not None \
                    else None
                if mission is not None:
                    result.append(Pairing(str(path), mission.name, variant.name,
                                          str(Path(world.path).resolve()), entry))
            self.name_variants(entry, failed, len(variants))
        return result

    def name_variants(self, entry: MissionEntry, failed: dict, variants: int) -> None:
        """Say on which world variants a mission does not load, when that depends on
        the variant: it loads on some, or not for the same reasons on all."""
        if not failed or (len(failed) == variants and len(set(failed.values())) == 1):
            return
        for variant in failed:
            self.diagnostics.append(variant.where.error(
                "mission-error", f"mission '{entry.path}' does not load on world variant "
                f"'{variant.name}'", "see the errors reported in the mission file"))

    def mission_path(self, entry: MissionEntry) -> Path | None:
        path = entry.path if entry.path.is_absolute() else self.spec.folder / entry.path
        if path.is_file():
            return path.resolve()
        near = [p.name for p in path.parent.glob("*.mission")] if path.parent.is_dir() else []
        self.diagnostics.append(entry.where.error(
            "mission-not-found", f"cannot find mission file '{entry.path}'",
            did_you_mean(path.name, near) or f"paths are relative to {self.spec.folder}"))
        return None

    def variant_world(self, variant: VariantEntry):
        try:
            world = load_world(variant.world, relative_to=self.spec.folder)
        except DiagnosticError as error:
            first = error.diagnostics[0]
            self.diagnostics.append(variant.where.error(
                "world-error", f"world variant '{variant.name}' does not load: {first.message}",
                first.hint))
            self.diagnostics.extend(d for d in error.diagnostics if d.span is not None)
            return None
        self.worlds[variant.name] = world
        return world

    def load(self, path: Path, world, failed: dict | None = None, variant=None):
        """The mission at ``path`` on ``world`` (its own when ``None``), or ``None``: its
        problems are reported, and kept in ``failed`` by ``variant`` when given."""
        try:
            return self.load_mission(path, world=world)
        except DiagnosticError as error:
            self.diagnostics.extend(error.diagnostics)
            if failed is not None:
                failed[variant] = frozenset(d for d in error.diagnostics if d.is_error)
            return None

    def names(self) -> None:
        for name, world in self.worlds.items():
            suffix = f" of world variant '{name}'" if len(self.worlds) > 1 else ""
            for move in self.spec.bodies:
                for body, span in zip(move.bodies, move.body_spans):
                    self.body(world, body, span, suffix, move.where.source)
            for noise in self.spec.postures:
                self.joints(world, noise, suffix)
            self.physics(world, suffix)
        self.solvers()

    def physics(self, world, suffix: str) -> None:
        """Physics can vary only where a mujoco driver simulates it; masses only of
        free bodies."""
        noise = self.spec.physics
        if not noise:
            return
        if not any(p.type == "mujoco" for p in world.processors.values()):
            self.diagnostics.append(noise.where.error(
                "no-physics", f"'physics' varies, but {world.path.name} simulates no physics", "run the missions on a world with a mujoco driver (a variant)"))
            return
        free = world.free_bodies()
        for (body, _), span in zip(noise.masses, noise.mass_spans):
            if body not in free:
                self.diagnostics.append(noise.where.source.error(
                    "body-not-free", f"cannot vary the mass of '{body}'{suffix}: it is not a "
                    "free body", span, did_you_mean(body, free)
                    or f"free bodies: {', '.join(free) or 'none'}"))

    def body(self, world, body: str, span, suffix: str, source) -> None:
        if not world.has_body(body):
            self.diagnostics.append(source.error(
                "unknown-body", f"unknown body '{body}'{suffix}", span,
                did_you_mean(body, world.body_names())))
        elif world.body(body).parent != ROOT:
            self.diagnostics.append(source.error(
                "body-not-fixed", f"body '{body}' is not fixed to the world (it hangs from "
                        f"'{world.body(body).parent}')", span,
                "only environment bodies and points attached to 'world' can be moved"))

    def joints(self, world, noise, suffix: str) -> None:
        names = world.group_names() + world.joint_names()
        if noise.joints not in names:
            self.diagnostics.append(noise.where.error(
                "unknown-joints", f"unknown joint group or joint '{noise.joints}'{suffix}",
                did_you_mean(noise.joints, names)))
            return
        group = world.joint_group(noise.joints)
        if len(group.q_indices) != group.dofs:
            self.diagnostics.append(noise.where.error(
                "wrong-joints", f"'{noise.joints}' has continuous or floating joints{suffix}",
                "posture noise applies to revolute and prismatic joints"))
            return
        distribution = noise.distribution
        sizes = {len(v) for v in vars(distribution).values() if v is not None}
        if not sizes <= {1, group.dofs}:
            self.diagnostics.append(noise.where.error(
                "wrong-length", f"'{noise.joints}' has {group.dofs} dofs{suffix}; give one value "
                        f"or {group.dofs}"))

    def solvers(self) -> None:
        from ..control.solvers import available_solvers

        installed = available_solvers()
        wheres = self.spec.settings_where.get("solver", ())
        for name, where in zip(self.spec.settings.get("solver", ()), wheres):
            if name not in installed:
                self.diagnostics.append(where.error(
                    "unknown-solver", f"unknown QP solver '{name}'",
                    did_you_mean(str(name), installed) or "installed: " + ", ".join(installed)))


def _stem(path) -> str:
    return Path(path).name.split(".")[0]
