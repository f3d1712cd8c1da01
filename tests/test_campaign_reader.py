"""Reading campaign files: the format, and located diagnostics for malformed ones."""

import textwrap

import pytest

from robocop_dsl.campaign import read_campaign
from robocop_dsl.campaign.spec import Normal, Uniform
from robocop_dsl.diagnostics import DiagnosticError, render_all


def write(tmp_path, text, name="test.campaign.yaml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text).lstrip(), encoding="utf-8")
    return path


def errors(path):
    with pytest.raises(DiagnosticError) as caught:
        read_campaign(path)
    return caught.value.diagnostics


def test_full_campaign_reads_into_spec(tmp_path):
    """Every section of the format lands in the spec, durations in seconds."""
    path = write(tmp_path, """
        campaign: bench
        description: moved parts
        missions:
          - pickup.mission
          - {path: other.mission, duration: 20 s, time_budget: 500ms}
        variants:
          sophia: bazar/sophia.yaml
        settings:
          solver: [proxqp, quadprog]
          hierarchy: strict
          time_step: [5ms, 0.01]
        samples: 8
        seed: 7
        duration: 60 s
        time_budget: 2
        vary:
          bodies:
            - move: [pickup_point, part_body]
              uniform: {low: [0.6, 0.1, 0.76], high: [0.8, 0.3, 0.76]}
            - move: drop_point
              normal: {std: 0.01}
          initial_posture:
            - joints: bazar_arms
              normal: {std: 0.05}
            - joints: bazar_ptu
              uniform: {low: -0.1, high: [0.1, 0.2]}
        """)
    spec = read_campaign(path)
    assert (spec.name, spec.description, spec.samples, spec.seed) == ("bench", "moved parts", 8, 7)
    assert (spec.duration, spec.time_budget) == (60.0, 2.0)
    assert [str(m.path) for m in spec.missions] == ["pickup.mission", "other.mission"]
    assert (spec.missions[1].duration, spec.missions[1].time_budget) == (20.0, 0.5)
    assert [(v.name, v.world) for v in spec.variants] == [("sophia", "bazar/sophia.yaml")]
    assert spec.settings == {"solver": ("proxqp", "quadprog"), "hierarchy": ("strict",),
                             "time_step": (0.005, 0.01)}
    first, second = spec.bodies
    assert first.bodies == ("pickup_point", "part_body")
    assert first.position == Uniform((0.6, 0.1, 0.76), (0.8, 0.3, 0.76))
    assert second.position == Normal((0.01, 0.01, 0.01), None)
    assert spec.postures[0].distribution == Normal((0.05,))
    assert spec.postures[1].distribution == Uniform((-0.1,), (0.1, 0.2))


def test_defaults(tmp_path):
    """A campaign that lists only missions runs one sample with seed 0 and the file's name."""
    spec = read_campaign(write(tmp_path, "missions: [a.mission]\n", "night.campaign.yaml"))
    assert (spec.name, spec.samples, spec.seed, spec.settings) == ("night", 1, 0, {})
    assert (spec.duration, spec.time_budget, spec.bodies, spec.postures) == (None, None, (), ())


def test_unknown_key_is_located_with_a_hint(tmp_path):
    """A misspelt key gives file, line, column, the source line, a caret and a hint."""
    path = write(tmp_path, """
        missions: [pickup.mission]
        sample: 10
        """)
    (diagnostic,) = errors(path)
    assert render_all([diagnostic]).splitlines() == [
        f"{path}:2:1: error[unknown-key]: unknown key 'sample'",
        " 2 | sample: 10",
        "   | ^^^^^^",
        "   = hint: did you mean 'samples'?",
    ]


def test_every_error_is_reported_at_once(tmp_path):
    """Problems in different sections are all reported, each on its own line."""
    path = write(tmp_path, """
        missions: [pickup.mission]
        samples: 0
        seed: -1
        duration: soon
        settings:
          hierarchy: strickt
          time_step: [5ms, fast]
        vary:
          bodies:
            - move: pickup_point
              uniform: {low: [0.8, 0.1, 0.76], high: [0.6, 0.3]}
            - move: [drop_point]
          initial_posture:
            - joints: bazar_arms
              normal: {std: -0.1, mean: 0}
        """)
    found = [(d.code, d.span.line, d.span.column, d.message) for d in errors(path)]
    assert found == [
        ("wrong-value", 2, 10, "'samples' must be an integer >= 1"),
        ("wrong-value", 3, 7, "'seed' must be an integer >= 0"),
        ("wrong-value", 4, 11, "'duration' must be a positive duration"),
        ("unknown-hierarchy", 6, 14, "unknown hierarchy 'strickt'"),
        ("wrong-value", 7, 20, "'time_step' must be a positive duration"),
        ("wrong-value", 11, 46, "'high' needs 3 values (x, y, z in metres)"),
        ("missing-key", 12, 7, "give exactly one of 'uniform:' or 'normal:'"),
        ("wrong-value", 15, 21, "'std' must not be negative"),
        ("unknown-key", 15, 27, "unknown key 'mean'"),
    ]


def test_low_above_high_is_an_error(tmp_path):
    """A uniform box whose low corner exceeds its high corner is refused."""
    path = write(tmp_path, """
        missions: [pickup.mission]
        vary:
          bodies:
            - move: pickup_point
              uniform: {low: [0.8, 0.1, 0.76], high: [0.6, 0.3, 0.76]}
        """)
    (diagnostic,) = errors(path)
    assert (diagnostic.code, diagnostic.span.line, diagnostic.message) == (
        "wrong-value", 5, "'low' must not exceed 'high'")


def test_missing_missions_and_bad_entries(tmp_path):
    """No 'missions:' list, and entries that are neither paths nor mappings, are errors."""
    assert [d.code for d in errors(write(tmp_path, "samples: 3\n"))] == ["missing-key"]
    path = write(tmp_path, """
        missions:
          - 3
          - {file: a.mission}
        """)
    found = [(d.code, d.span.line) for d in errors(path)]
    assert found == [("wrong-value", 2), ("wrong-value", 3)]


def test_malformed_yaml_is_located(tmp_path):
    """Broken YAML is reported at the place the parser stopped."""
    (diagnostic,) = errors(write(tmp_path, "missions: [a.mission\nseed: 1\n"))
    assert diagnostic.message.startswith("malformed YAML")
    assert diagnostic.span.line == 2


def test_top_level_must_be_a_mapping(tmp_path):
    """A campaign that is a bare list names what a campaign file must be."""
    (diagnostic,) = errors(write(tmp_path, "- a.mission\n"))
    assert (diagnostic.code, diagnostic.message) == (
        "not-a-campaign", "a campaign file must be a mapping with a 'missions:' list")


def test_missing_file(tmp_path):
    """A campaign file that does not exist is a diagnostic naming it."""
    (diagnostic,) = errors(tmp_path / "absent.campaign.yaml")
    assert diagnostic.code == "unreadable-file" and "absent.campaign.yaml" in diagnostic.message
