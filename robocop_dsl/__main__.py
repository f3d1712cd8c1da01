"""``python -m robocop_dsl`` runs the ``robocop-mission`` command line."""

from .cli.main import entry_point

entry_point()
