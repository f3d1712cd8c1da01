"""`check` on the settings of the vocabulary: tolerances, `enabled`, `interpolated`,
per-axis body velocity limits, per-dof gains, limits inverted by an action."""

import math
from pathlib import Path

import pytest

from robocop_dsl.compile import WorldCache, check_source

REPO = Path(__file__).resolve().parent.parent
BASE = (REPO / "tests" / "fixtures" / "valid" / "base.mission").read_text()
CACHE = WorldCache()
TOOL = "bazar_left_hankamp_tool_object_side"


def checked(text: str):
    return check_source(text, REPO / "tests" / "fixtures" / "valid" / "m.mission",
                        cache=CACHE)


def variant(*replacements) -> str:
    """The fixtures' base mission with ``(old, new)`` replacements, each found once."""
    text = BASE
    for old, new in replacements:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    return text


def codes(result):
    return [(d.code, d.span.line if d.span else None) for d in result.diagnostics]


ARMS = "    feedback     = proportional(gain = 1)\n}"
TOOL_TASK = "    feedback     = proportional(gain = 5)\n}"
LIMITS = "    max_acceleration = 5 rad/s^2\n}"


@pytest.mark.parametrize("arms, tool", [
    ("tolerance = 0.2 deg", "tolerance = 2 mm"),
    ("tolerance = [1, 1, 1, 1, 1, 1, 1, 2, 2, 2, 2, 2, 2, 2] deg", "tolerance = 3 deg"),
    ("gain = [1, 1, 1, 1, 2, 2, 2, 1, 1, 1, 1, 2, 2, 2]",
     "tolerance = pose(position = 2 mm, orientation = 1 deg)"),
    ("enabled = true", "gain = [5, 5, 5, 2, 2, 2]"),
])
def test_valid_settings_check_clean(arms, tool):
    result = checked(variant((ARMS, ARMS[:-1] + f"    {arms}\n}}"),
                             (TOOL_TASK, TOOL_TASK[:-1] + f"    {tool}\n}}")))
    assert result.diagnostics == ()


def test_compiled_settings_in_si():
    result = checked(variant(
        (ARMS, ARMS[:-1] + "    enabled = true\n    gain = [1, 1, 1, 1, 2, 2, 2, "
         "1, 1, 1, 1, 2, 2, 2]\n}"),
        (TOOL_TASK, TOOL_TASK[:-1] + "    tolerance = 2 deg\n}"),
        (LIMITS, LIMITS[:-1] + "    enabled = false\n}"),
        ("task arms:", f"constraint speed: body_velocity({TOOL}) {{\n"
         "    max_linear = [50, 50, 20] cm/s\n    max_angular = 1 rad/s\n}\n\ntask arms:"),
        ("when arms.reached", "when arms.interpolated")))
    assert result.diagnostics == ()
    mission = result.mission
    arms, tool = mission.tasks["arms"], mission.tasks["left_tool"]
    assert arms.enabled and not tool.enabled
    assert arms.gain == (1, 1, 1, 1, 2, 2, 2) * 2 and tool.gain is None
    assert arms.tolerance == pytest.approx((math.radians(0.5),) * 14)
    assert tool.tolerance == pytest.approx((0.001, math.radians(2)))
    assert not mission.constraints["limits"].enabled
    speed = mission.constraints["speed"]
    assert speed.enabled and "enabled" not in speed.parameters
    assert speed.parameters["max_linear"] == pytest.approx((0.5, 0.5, 0.2))
    assert speed.parameters["max_angular"] == 1.0
    first = mission.states["ready"].transitions[0]
    assert first.text == "arms.interpolated"


@pytest.mark.parametrize("setting, code, message", [
    ("tolerance = 2 mm", "wrong-dimension", "'tolerance' expects an angle"),
    ("tolerance = [1, 2] deg", "wrong-length", "'tolerance' has 2 values, expected 14"),
    ("tolerance = 0 deg", "wrong-value", "'tolerance' must not be zero"),
    ("gain = [1, 2]", "wrong-length", "'gain' has 2 values, expected 14"),
    ("gain = 1 m", "wrong-dimension", "'gain' is a plain number"),
    ("enabled = 1", "wrong-value", "'enabled' expects true or false"),
])
def test_joint_task_settings_are_checked(setting, code, message):
    result = checked(variant((ARMS, ARMS[:-1] + f"    {setting}\n}}")))
    [diagnostic] = result.diagnostics
    assert (diagnostic.code, diagnostic.span.line) == (code, 13)
    assert diagnostic.message.startswith(message)


@pytest.mark.parametrize("setting, code, message", [
    ("tolerance = 0.002", "wrong-value", "'tolerance' has no unit"),
    ("tolerance = twist(linear = 1 mm/s)", "wrong-value",
     "'tolerance' of both parts is written pose(...)"),
    ("tolerance = pose(position = 1 deg)", "wrong-dimension",
     "'tolerance' (position) expects a length"),
    ("gain = [1, 2, 3]", "wrong-length", "'gain' has 3 values, expected 6"),
])
def test_body_task_settings_are_checked(setting, code, message):
    result = checked(variant((TOOL_TASK, TOOL_TASK[:-1] + f"    {setting}\n}}")))
    [diagnostic] = result.diagnostics
    assert (diagnostic.code, diagnostic.span.line) == (code, 18)
    assert diagnostic.message.startswith(message)


def test_interpolated_is_a_flag():
    result = checked(variant(("when arms.reached", "when arms.interpolated < 1")))
    assert [(d.code, d.message) for d in result.diagnostics] == [
        ("wrong-condition", "'arms.interpolated' is true or false, it cannot be compared")]
    result = checked(variant(("when arms.reached", "when arms.interpolatd")))
    assert result.diagnostics[0].hint == "did you mean 'interpolated'?"


def test_enabled_is_not_set_by_an_action():
    result = checked(variant(("exit { disable arms }", "exit { arms.enabled = false }")))
    [diagnostic] = result.diagnostics
    assert diagnostic.code == "unknown-field"
    assert diagnostic.hint == "write: enable arms (or disable arms)"


def test_a_task_enabled_from_the_start_is_read_without_warning():
    """No state enables left_tool: a warning, unless it is declared `enabled = true`."""
    unenabled = ("        enable left_tool\n", "")
    assert codes(checked(variant(unenabled))) == [("task-never-enabled", 36)] * 2
    assert checked(variant(unenabled, (TOOL_TASK, TOOL_TASK[:-1] + "    enabled = true\n}"))
                   ).diagnostics == ()


def test_limits_that_leave_a_joint_no_position_within_its_urdf_range():
    """A declared range that does not meet a joint's URDF range: the first such joint,
    its value and the URDF's limit."""
    result = checked(variant((LIMITS, LIMITS[:-1] + "    min_position = 1 rad\n"
                                                   "    max_position = 1 rad\n}")))
    [diagnostic] = result.diagnostics
    assert diagnostic.code == "inverted-limits"
    assert diagnostic.message == ("'min_position' is above the URDF's upper limit at joint "
                                  "16 of 'bazar_upper_joints': 1 > 0.54 rad")


def test_limits_inverted_by_an_action():
    """An action is judged against the declared limit it leaves, or the one assigned in
    the same block; a block that assigns both in order passes."""
    declared = (LIMITS, LIMITS[:-1] + "    max_position = 1 rad\n}")
    result = checked(variant(declared, ("        enable left_tool\n",
                                        "        enable left_tool\n"
                                        "        limits.min_position = 1.5 rad\n")))
    [diagnostic] = result.diagnostics
    assert (diagnostic.code, diagnostic.span.line, diagnostic.span.column) == (
        "inverted-limits", 36, 31)
    assert diagnostic.message == (
        "'min_position' is above 'max_position' at joint 1 of 'bazar_upper_joints': "
        "1.5 > 1 rad, 'max_position' as declared at line 8 (and 15 more joints)")
    both = checked(variant(declared, ("        enable left_tool\n",
                                      "        enable left_tool\n"
                                      "        limits.max_position = 2 rad\n"
                                      "        limits.min_position = 0.5 rad\n")))
    assert both.diagnostics == ()
    in_transition = checked(variant(("when arms.reached -> approach",
                                     "when arms.reached -> approach "
                                     "{ limits.max_position = -3 rad }")))
    assert codes(in_transition) == [("inverted-limits", 28)]
