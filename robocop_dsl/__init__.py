"""robocop-mission: RoboCoP-style worlds, a kinematic QP controller and missions as text."""

__version__ = "0.1.0"
