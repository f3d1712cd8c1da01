"""Property: no mission text, however broken, makes parsing, checking or compiling raise."""

import tempfile
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from robocop_dsl.compile import WorldCache, check_file, check_source
from robocop_dsl.diagnostics import Diagnostic

REPO = Path(__file__).resolve().parent.parent
SEEDS = [p.read_text() for p in sorted((REPO / "missions").glob("*.mission"))]
TOKENS = ["{", "}", "(", ")", "[", "]", "->", "=", ":", ",", ".", "\n", " ", "#", '"',
          "when", "state", "final", "task", "enable", "offset", "and", "not", "rad", "mm",
          "1e999", "-3", "0.5", "pose(", "otg(", "arms", "left_tool", "elapsed", "<", ">=",
          "current", "world", "controller.failed", "event", "emit", "log", "start", "[1, 2]",
          "var", "var n: count = 0", "var z: length", "n = n + 1", "z = z * 2 - 1 mm", "+",
          "*", "/", "force(", "force(left_tool).z", "torque(", "contact(", "contact(a, b)",
          "N", "Nm", "(m/s)/N", "count", "position", '"{n}"', "{", ".position.z", "z"]

LIBRARY = "bazar_common.mission"
COMPOSITE = [(p.read_text(), (REPO / "missions" / LIBRARY).read_text())
             for p in sorted((REPO / "missions").glob("*.mission"))
             if f'import "{LIBRARY}"' in p.read_text()]
COMPOSITE_TOKENS = TOKENS + [
    "import", 'import "bazar_common.mission"', 'import "mission.mission"', "let", "library",
    "behavior", "region", "parallel", "done", ".done", ".visits", "visits", "failure",
    "approach(", "go_home(", "transfer(", "approach(left_tool, pickup_point)", "height",
    "height = 2 s", "tool", "point", "length", "duration", "body", "target", "-", "-height",
    "[0, 0, height]", "[0, 0, -approach_height] cm", "approach_height", "home_posture",
    "state s: approach(right_tool, drop_point)", "region r: go_home(arms)", "final f: failure",
    "both.left.missed", "when x.done -> y", "state p: parallel {", "let x = pickup_point"]
CACHE = WorldCache()
FOLDER = Path(tempfile.mkdtemp(prefix="robocop-property-"))


def _mutate(draw, text: str, tokens: list[str]) -> str:
    """``text`` with a few spans deleted, duplicated or replaced by tokens."""
    for _ in range(draw(st.integers(1, 4))):
        start = draw(st.integers(0, len(text)))
        end = min(len(text), start + draw(st.integers(0, 40)))
        edit = draw(st.sampled_from(["delete", "insert", "replace", "duplicate"]))
        token = draw(st.sampled_from(tokens))
        if edit == "delete":
            text = text[:start] + text[end:]
        elif edit == "insert":
            text = text[:start] + token + text[start:]
        elif edit == "replace":
            text = text[:start] + token + text[end:]
        else:
            text = text[:end] + text[start:end] + text[end:]
    return text


@st.composite
def mutated_missions(draw) -> str:
    """A real mission with a few spans deleted, duplicated or replaced by tokens."""
    return _mutate(draw, draw(st.sampled_from(SEEDS)), TOKENS)


@st.composite
def mutated_composites(draw) -> tuple[str, str]:
    """A mission and the library it imports, one or both of them mutated."""
    mission, library = draw(st.sampled_from(COMPOSITE))
    which = draw(st.sampled_from(["mission", "library", "both"]))
    if which != "library":
        mission = _mutate(draw, mission, COMPOSITE_TOKENS)
    if which != "mission":
        library = _mutate(draw, library, COMPOSITE_TOKENS)
    return mission, library


def _parse_and_check(text: str, world) -> tuple[Diagnostic, ...]:
    """Parse, check, build and check the state graph, compile when clean."""
    return check_source(text, "fuzz.mission", world=world).diagnostics


def _assert_diagnostics(diagnostics) -> None:
    for diagnostic in diagnostics:
        assert isinstance(diagnostic, Diagnostic)
        assert diagnostic.code and diagnostic.message


@settings(max_examples=1000, deadline=None, suppress_health_check=list(HealthCheck))
@given(text=mutated_missions())
def test_mutated_missions_only_give_diagnostics(text, bazar):
    """1,000 mutated missions: every problem is a located Diagnostic, nothing raises."""
    _assert_diagnostics(_parse_and_check(text, bazar))


@settings(max_examples=300, deadline=None, suppress_health_check=list(HealthCheck))
@given(text=st.lists(st.sampled_from(TOKENS + ["a", "x1", "_", "9", "\t"]), max_size=80)
       .map(" ".join))
def test_token_soup_only_gives_diagnostics(text, bazar):
    """Random sequences of the language's tokens never make the pipeline raise."""
    _assert_diagnostics(_parse_and_check(text, bazar))


@settings(max_examples=1000, deadline=None, suppress_health_check=list(HealthCheck))
@given(files=mutated_composites())
def test_mutated_composites_only_give_diagnostics(files):
    """1,000 composite missions with the mutated library they import (both written to a
    folder so that the import resolves; the world loaded once): every problem is a
    Diagnostic, in the mission or the library, and nothing raises."""
    mission, library = files
    (FOLDER / LIBRARY).write_text(library)
    path = FOLDER / "mission.mission"
    path.write_text(mission)
    result = check_file(path, cache=CACHE)
    _assert_diagnostics(result.diagnostics)
    assert {Path(d.file).name for d in result.diagnostics
            if d.file.endswith(".mission")} <= {path.name, LIBRARY}
