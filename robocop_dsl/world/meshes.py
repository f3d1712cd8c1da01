"""The mesh files a URDF names: which may be read, and whether a collision mesh loads.

A mesh is read only when it is a regular file (after following links) whose name and
target end with a mesh format's extension (:data:`MESH_SUFFIXES`); anything else
(``/etc/passwd``, ``/dev/zero``, a FIFO) is refused on its name and ``stat`` alone.
A collision mesh is loaded by coal's loader (assimp), what pinocchio builds the
collision geometry with; what the loader says of each URDF's collision meshes is kept
in the user's private cache folder, in a file named after a digest of their paths,
sizes and modification times, so that a world loaded again imports neither coal nor
assimp.
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from pathlib import Path

from .. import __version__
from ..resources import private_cache_file
from ..sources import file_refusal

MESH_SUFFIXES = (".stl", ".dae", ".obj", ".ply", ".msh")
"""Mesh formats: those assimp reads that URDFs use, and MuJoCo's own."""
_FORMAT = 1
"""Bumped whenever what is stored changes."""
_LFS_POINTER = b"version https://git-lfs"
_LOADED: dict = {}
"""``(path, size, modification time [ns])`` -> what the loader said, ``None`` if it
loaded, for this process."""


def mesh_refusal(name: str, path: Path) -> str | None:
    """Why the mesh written ``name`` (a path or URI), found at ``path``, may not be
    read, or ``None`` when it may (the file is not opened)."""
    expected = ", ".join(MESH_SUFFIXES)
    if Path(name).suffix.lower() not in MESH_SUFFIXES:
        return f"not a mesh file (the name must end with {expected})"
    return file_refusal(path, MESH_SUFFIXES, expected)


def load_problems(paths: list[Path]) -> dict[Path, str]:
    """What coal's mesh loader says of each of ``paths`` (regular mesh files) that it
    cannot load, by path; the meshes that load are left out."""
    stamps = {path: _stamp(path) for path in dict.fromkeys(paths)}
    if not stamps:
        return {}
    cache = _cache_file(list(stamps.values()))
    stored = _read(cache)
    if stored is None:
        stored = {str(path): _loaded(stamp) for path, stamp in stamps.items()}
        _write(cache, stored)
    return {path: stored[str(path)] for path in stamps if stored.get(str(path))}


def lfs_pointer(path: Path) -> bool:
    """Whether ``path`` (a regular file) is a Git LFS pointer, not the file it stands
    for."""
    try:
        with open(path, "rb") as file:
            return file.read(len(_LFS_POINTER)) == _LFS_POINTER
    except OSError:
        return False


def _stamp(path: Path) -> tuple:
    try:
        info = os.stat(path)
    except OSError:
        return (str(path), None, None)
    return (str(path), info.st_size, info.st_mtime_ns)


def _loaded(stamp: tuple) -> str | None:
    """What the loader says of the mesh ``stamp`` names (``None``: it loads)."""
    if stamp not in _LOADED:
        _LOADED[stamp] = _load(Path(stamp[0]))
    return _LOADED[stamp]


def _load(path: Path) -> str | None:
    import coal
    import numpy as np

    try:
        coal.MeshLoader().load(str(path), np.ones(3))
    except (ValueError, RuntimeError, MemoryError) as error:
        return _said(str(error), path)
    return None


def _said(text: str, path: Path) -> str:
    """The loader's own words in ``text`` (coal's message, without its source location,
    the resource line or the hint on folders), the path shortened to the file's name."""
    message = text.split("message:", 1)[-1]
    lines = [line.strip() for line in message.splitlines()
             if line.strip() and not line.strip().startswith(("Could not load resource",
                                                              "Hint:"))]
    return " ".join(lines).replace(str(path), path.name) or "the loader refused it"


def _cache_file(stamps: list) -> str | None:
    digest = hashlib.sha256(json.dumps([_FORMAT, __version__, sorted(stamps)]).encode())
    return private_cache_file(f"mesh-loads-{digest.hexdigest()[:32]}.json")


def _read(path: str | None) -> dict | None:
    if path is None:
        return None
    try:
        with open(path, encoding="utf-8") as file:
            stored = json.load(file)
    except (OSError, ValueError):
        return None
    well_formed = isinstance(stored, dict) and all(
        isinstance(value, (str, type(None))) for value in stored.values())
    return stored if well_formed else None


def _write(path: str | None, stored: dict) -> None:
    """Replace the cache file whole (a reader never sees half of it); a folder that
    cannot be written is no error."""
    if path is None:
        return
    try:
        handle, temporary = tempfile.mkstemp(dir=os.path.dirname(path), suffix=".tmp")
        with os.fdopen(handle, "w", encoding="utf-8") as file:
            json.dump(stored, file)
        os.replace(temporary, path)
    except OSError:
        return
