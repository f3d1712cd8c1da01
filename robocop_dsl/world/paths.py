"""The robots path: where world files, URDFs and ``package://`` resources are found.

Order: the including file's folder, the package's ``robots/``, each ``ROBOCOP_PATH``
entry (``os.pathsep``-separated), then the data folders of installed robot-description
packages (``example-robot-data`` installs its robots under ``cmeel.prefix/share``).
"""

from __future__ import annotations

import os
import site
import sysconfig
from pathlib import Path

from ..resources import ROBOTS_DIR


def _installed_share_dirs() -> list[Path]:
    candidates = [sysconfig.get_paths()["purelib"], *site.getsitepackages()]
    found = []
    for folder in dict.fromkeys(candidates):
        share = Path(folder) / "cmeel.prefix" / "share"
        if share.is_dir():
            found.append(share)
    return found


def robots_path() -> list[Path]:
    """The folders searched after the including file's own folder."""
    extra = [Path(p) for p in os.environ.get("ROBOCOP_PATH", "").split(os.pathsep) if p]
    return [ROBOTS_DIR, *extra, *_installed_share_dirs()]


def search_folders(relative_to: Path | None) -> list[Path]:
    folders = [relative_to] if relative_to is not None else []
    return folders + robots_path()


def resolve(name: str, relative_to: Path | None) -> Path | None:
    """Find ``name`` (a relative path or a ``package://`` URI); ``None`` when absent."""
    if name.startswith("package://"):
        name = name[len("package://"):]
    elif name.startswith("file://"):
        name = name[len("file://"):]
    candidate = Path(name)
    try:
        if candidate.is_absolute():
            return candidate if candidate.exists() else None
        for folder in search_folders(relative_to):
            path = folder / candidate
            if path.exists():
                return path.resolve()
    except (OSError, ValueError):  # a name the file system cannot hold is not found
        return None
    return None


def resolve_world_path(name: str | Path, relative_to: Path | None = None) -> Path | None:
    """Resolve a world file named by a user or a mission.

    An existing path (relative to the working folder) wins; otherwise the name is looked
    up relative to ``relative_to`` and then along the robots path.
    """
    direct = Path(name)
    if relative_to is None and direct.is_file():
        return direct.resolve()
    return resolve(str(name), relative_to)
