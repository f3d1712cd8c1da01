"""Folders shipped with the package (the grammar and the bundled robots) and the user's
private cache folder.

In an installed wheel the shipped folders sit inside the package; in a source checkout
they are the top-level ``grammar/`` and ``robots/`` folders beside it.
"""

import os
import stat
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent


def shipped_dir(name: str) -> Path:
    """Return the shipped folder ``name`` (``"grammar"`` or ``"robots"``)."""
    installed = _PACKAGE / name
    if installed.is_dir():
        return installed
    return _PACKAGE.parent / name


GRAMMAR_DIR = shipped_dir("grammar")
ROBOTS_DIR = shipped_dir("robots")


def private_cache_file(name: str) -> str | None:
    """The path of cache file ``name`` in ``$XDG_CACHE_HOME/robocop-mission``
    (``~/.cache``), made if need be, or ``None`` unless that folder and any file already
    there are the user's own and no one else may write to them (what is read back from
    it must be what this user wrote)."""
    root = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    folder = os.path.join(root, "robocop-mission")
    path = os.path.join(folder, name)
    try:
        os.makedirs(folder, mode=0o700, exist_ok=True)
        if not _private(os.stat(folder)):
            return None
        if os.path.lexists(path) and not _private(os.lstat(path)):
            return None
    except OSError:
        return None
    return path


def _private(info: os.stat_result) -> bool:
    """A folder or a regular file owned by this user that no one else may write to."""
    kind = stat.S_ISDIR(info.st_mode) or stat.S_ISREG(info.st_mode)
    return kind and info.st_uid == os.getuid() and not info.st_mode & 0o022
