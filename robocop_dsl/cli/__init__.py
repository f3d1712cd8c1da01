"""The ``robocop-mission`` command line: a thin layer over the Python API."""
