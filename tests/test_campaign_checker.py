"""Checking a campaign against its real missions and worlds before anything runs."""

import textwrap

import pytest

from robocop_dsl.campaign import load_campaign
from robocop_dsl.diagnostics import DiagnosticError

from conftest import MISSIONS

PICKUP = MISSIONS / "pickup.mission"


def campaign(tmp_path, text):
    path = tmp_path / "checked.campaign.yaml"
    path.write_text(textwrap.dedent(text).lstrip(), encoding="utf-8")
    return path


def diagnostics(path):
    with pytest.raises(DiagnosticError) as caught:
        load_campaign(path)
    return caught.value.diagnostics


def test_valid_campaign_expands_on_the_mission_world(tmp_path):
    """Without variants, a mission runs on the world it names, one job per sample."""
    loaded = load_campaign(campaign(tmp_path, f"""
        missions: [{PICKUP}]
        samples: 4
        settings: {{solver: [proxqp, daqp]}}
        """))
    assert len(loaded.jobs) == 8
    assert {(j.mission_name, j.variant) for j in loaded.jobs} == {("pickup", "sophia")}
    assert loaded.jobs[0].world.endswith("bazar/sophia.yaml")


def test_names_are_checked_against_the_world(tmp_path):
    """Unknown bodies, bodies carried by the robot, unknown groups and solvers, and
    lists of the wrong length are all located in the campaign file, with hints."""
    path = campaign(tmp_path, f"""
        missions: [{PICKUP}]
        settings: {{solver: proxpq}}
        vary:
          bodies:
            - move: [pickup_piont, bazar_left_hankamp_tool_object_side]
              normal: {{std: 0.01}}
          initial_posture:
            - joints: bazar_armz
              normal: {{std: 0.1}}
            - joints: bazar_ptu
              uniform: {{low: [-0.1, -0.1, -0.1], high: 0.1}}
        """)
    found = [(d.code, d.span.line, d.span.column, d.message, d.hint) for d in diagnostics(path)]
    assert found == [
        ("unknown-solver", 2, 20, "unknown QP solver 'proxpq'", "did you mean 'proxqp'?"),
        ("unknown-body", 5, 14, "unknown body 'pickup_piont'", "did you mean 'pickup_point'?"),
        ("body-not-fixed", 5, 28, "body 'bazar_left_hankamp_tool_object_side' is not fixed to "
         "the world (it hangs from 'bazar_left_hankamp_tool_robot_side')",
         "only environment bodies and points attached to 'world' can be moved"),
        ("unknown-joints", 8, 15, "unknown joint group or joint 'bazar_armz'",
         "did you mean 'bazar_arms'?"),
        ("wrong-length", 10, 15, "'bazar_ptu' has 2 dofs; give one value or 2", None),
    ]


def test_missing_mission_and_broken_variant(tmp_path):
    """A mission file that is not there and a variant that does not load are located."""
    (tmp_path / "pickup.mission").write_text(PICKUP.read_text(), encoding="utf-8")
    path = campaign(tmp_path, """
        missions: [pikup.mission]
        variants:
          nowhere: bazar/nowhere.yaml
        """)
    found = [(d.code, d.span.line, d.message, d.hint) for d in diagnostics(path)]
    assert found[0] == ("mission-not-found", 1, "cannot find mission file 'pikup.mission'",
                        "did you mean 'pickup.mission'?")
    assert found[1][:2] == ("world-error", 3)
    assert "nowhere.yaml" in found[1][2]


def test_an_invalid_mission_stops_the_campaign(tmp_path):
    """A mission with an error gives its own diagnostics, located in the mission file."""
    broken = tmp_path / "broken.mission"
    broken.write_text(PICKUP.read_text().replace("enable left_tool", "enable left_tol"),
                      encoding="utf-8")
    found = diagnostics(campaign(tmp_path, "missions: [broken.mission]\n"))
    assert found and all(d.file == str(broken) for d in found)
    assert any("left_tol" in d.message for d in found)


def test_a_mission_that_loads_on_some_variants_only_names_the_others(tmp_path):
    """The variant a mission does not load on is named in the campaign file; the
    mission's errors on it follow, located in the mission file."""
    path = campaign(tmp_path, f"""
        missions: [{PICKUP}]
        variants:
          sophia: bazar/sophia.yaml
          cell: bazar/workcell.yaml
        """)
    found = diagnostics(path)
    named = [(d.code, d.span.line, d.message) for d in found if d.file == str(path)]
    assert named == [("mission-error", 4, f"mission '{PICKUP}' does not load on world "
                      "variant 'cell'")]
    assert any(d.code == "unknown-body" and "kinect2_rgb_optical_frame" in d.message
               and d.file == str(PICKUP) for d in found)


def test_a_mission_broken_alike_on_every_variant_names_none(tmp_path):
    """A mission error that does not depend on the world is the mission's alone."""
    broken = tmp_path / "broken.mission"
    broken.write_text(PICKUP.read_text().replace("enable left_tool", "enable left_tol"),
                      encoding="utf-8")
    found = diagnostics(campaign(tmp_path, """
        missions: [broken.mission]
        variants:
          one: bazar/sophia.yaml
          two: bazar/sophia_seat.yaml
        """))
    assert found and all(d.file == str(broken) for d in found)
