"""What ``check`` asks of a world's collision geometry, kept from one run to the next.

Which bodies have collision geometry, and which pairs of two sets are closer than some
distance in the world's initial posture, take the shapes built (pinocchio, coal, the
convex hull of each mesh) and placed: more than the rest of a ``check``. The answers
are stored as JSON in the user's private cache folder
(:func:`~robocop_dsl.resources.private_cache_file`), in a file named after a digest of
everything they depend on: the assembled URDF, the size and modification time of each
mesh file it names, the initial posture, the joint groups and the allowed collisions.
Any change to those gives another file, so an answer is never read for another world;
without a private cache folder, or with a file that does not read back, they are
computed again.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import tempfile
import weakref
from weakref import WeakKeyDictionary

from .. import __version__
from ..resources import private_cache_file
from .collisions import bodies_of_set
from .world import World

_FORMAT = 1
"""Bumped whenever what is stored, or how it is computed, changes."""
_MESH = re.compile(r'<mesh\b[^>]*\bfilename="([^"]*)"')
_FACTS: WeakKeyDictionary = WeakKeyDictionary()


def collision_facts(world: World) -> "CollisionFacts":
    """The collision facts of ``world`` (one object per loaded world)."""
    if world not in _FACTS:
        _FACTS[world] = CollisionFacts(world)
    return _FACTS[world]


class CollisionFacts:
    """Answers about a world's collision geometry, from the cache file when it has them.
    It refers to its world weakly: kept in a table keyed weakly by the world, it must
    not keep that world alive.

    Args:
        world: The loaded world.
    """

    def __init__(self, world: World):
        self._world = weakref.ref(world)
        self._path = private_cache_file(f"world-collisions-{fingerprint(world)[:32]}.json")
        self._stored = self._read()

    @property
    def world(self) -> World:
        return self._world()

    def set_bodies(self, name: str) -> tuple[str, ...]:
        """The bodies with collision geometry that set ``name`` stands for (see
        :func:`~robocop_dsl.world.collisions.set_bodies`).

        Raises:
            KeyError: ``name`` is neither a body, a joint group nor a joint.
        """
        if "bodies" not in self._stored:
            from .collisions import collision_geometry

            self._store("bodies", list(collision_geometry(self.world).by_body))
        return bodies_of_set(self.world, name, set(self._stored["bodies"]))

    def closest_at_start(self, first: str, second: str,
                         min_distance: float) -> list[tuple[str, str, float]]:
        """The shape pairs between sets ``first`` and ``second`` closer than
        ``min_distance`` [m] in the world's initial posture, as ``(body, body, distance
        [m])`` in the order :meth:`CollisionScene.closest
        <robocop_dsl.world.collision_scene.CollisionScene.closest>` gives them."""
        key = f"{first}\t{second}\t{min_distance!r}"
        closest = self._stored.get("closest", {})
        if key not in closest:
            closest = {**closest, key: _closest(self.world, first, second, min_distance)}
            self._store("closest", closest)
        return [(a, b, float(distance)) for a, b, distance in self._stored["closest"][key]]

    def _read(self) -> dict:
        if self._path is None:
            return {}
        try:
            with open(self._path, encoding="utf-8") as file:
                stored = json.load(file)
        except (OSError, ValueError):
            return {}
        return stored if _well_formed(stored) else {}

    def _store(self, name: str, value) -> None:
        """Keep ``value`` as ``name``, and write the file again (replaced whole, so that
        a reader never sees half of it); a folder that cannot be written is no error."""
        self._stored = {**self._stored, name: value}
        if self._path is None:
            return
        folder = os.path.dirname(self._path)
        try:
            handle, temporary = tempfile.mkstemp(dir=folder, suffix=".tmp")
            with os.fdopen(handle, "w", encoding="utf-8") as file:
                json.dump(self._stored, file)
            os.replace(temporary, self._path)
        except OSError:
            return


def _well_formed(stored) -> bool:
    """Whether ``stored`` is what :class:`CollisionFacts` writes (a damaged file is
    ignored: its answers are computed again)."""
    if not isinstance(stored, dict):
        return False
    bodies = stored.get("bodies", [])
    closest = stored.get("closest", {})
    return (isinstance(bodies, list) and all(isinstance(b, str) for b in bodies)
            and isinstance(closest, dict)
            and all(isinstance(found, list) and all(
                isinstance(row, list) and len(row) == 3 and isinstance(row[0], str)
                and isinstance(row[1], str) and isinstance(row[2], (int, float))
                for row in found) for found in closest.values()))


def fingerprint(world: World) -> str:
    """A digest of everything the collision facts of ``world`` depend on."""
    assembly = world._assembly
    meshes = []
    for path in sorted(set(_MESH.findall(assembly.urdf))):
        try:
            info = os.stat(path)
            meshes.append((path, info.st_size, info.st_mtime_ns))
        except OSError:
            meshes.append((path, None, None))
    described = [_FORMAT, __version__, assembly.urdf, meshes,
                 sorted((name, [float(v) for v in values])
                        for name, values in assembly.initial.items()),
                 sorted(sorted(pair) for pair in assembly.allowed_collisions),
                 sorted((name, list(group.joints)) for name, group in assembly.groups.items())]
    return hashlib.sha256(json.dumps(described).encode()).hexdigest()


def _closest(world: World, first: str, second: str,
             min_distance: float) -> list[tuple[str, str, float]]:
    """:meth:`CollisionFacts.closest_at_start`, measured."""
    from ..control.kinematics import Kinematics
    from .collision_scene import CollisionScene
    from .collisions import checked_pairs

    scene = CollisionScene(world, checked_pairs(world, first, second))
    kinematics = Kinematics(world)
    kinematics.update(world.initial_configuration())
    scene.place(kinematics)
    return [(w.first.body, w.second.body, float(w.distance))
            for w in scene.closest(min_distance)]
