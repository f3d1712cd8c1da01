"""The range_* broken missions, made valid with the smallest valid values, pass check and run."""

from pathlib import Path

import pytest

from robocop_dsl.compile import check_file
from robocop_dsl.runtime import load_mission

INVALID = Path(__file__).resolve().parent / "fixtures" / "invalid"

# Fixture, the value out of range as written, the nearest valid value.
BORDERLINE = [
    ("range_zero_max_velocity", "max_velocity     = 0 rad/s", "max_velocity     = 1e-3 rad/s"),
    ("range_zero_duration", "duration = 0 s", "duration = 1 ms"),
    ("range_negative_gain", "ki = -0.5", "ki = 0"),
    ("range_min_above_max", "max_position     = -1 rad", "max_position     = 0.5 rad"),
    ("range_min_above_urdf", "min_position     = 3 rad", "min_position     = 0.54 rad"),
    ("range_per_dof_element", "1, 0, 1", "1, 1e-3, 1"),
    ("range_negative_weight", "weight       = -2", "weight       = 0"),
]


@pytest.mark.parametrize("name, bad, borderline", BORDERLINE, ids=[b[0] for b in BORDERLINE])
def test_borderline_mission_checks_and_runs(tmp_path, name, bad, borderline):
    """The fixture's error is gone at the range's edge, and half a second runs cleanly."""
    text = (INVALID / f"{name}.mission").read_text()
    assert text.count(bad) == 1
    path = tmp_path / f"{name}.mission"
    path.write_text(text.replace(bad, borderline))
    assert check_file(path).diagnostics == ()
    result = load_mission(path).runner().run(duration=0.5)
    assert result.outcome == "stopped"
