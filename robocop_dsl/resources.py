"""Folders shipped with the package: the grammar and the bundled robots.

In an installed wheel they sit inside the package; in a source checkout they are the
top-level ``grammar/`` and ``robots/`` folders beside it.
"""

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
