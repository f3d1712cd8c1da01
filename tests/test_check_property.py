"""Property: no mission text, however broken, makes parsing, checking or compiling raise."""

from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from robocop_dsl.compile import check_source
from robocop_dsl.diagnostics import Diagnostic

REPO = Path(__file__).resolve().parent.parent
SEEDS = [p.read_text() for p in sorted((REPO / "missions").glob("*.mission"))]
TOKENS = ["{", "}", "(", ")", "[", "]", "->", "=", ":", ",", ".", "\n", " ", "#", '"',
          "when", "state", "final", "task", "enable", "offset", "and", "not", "rad", "mm",
          "1e999", "-3", "0.5", "pose(", "otg(", "arms", "left_tool", "elapsed", "<", ">=",
          "current", "world", "controller.failed", "event", "emit", "log", "start", "[1, 2]"]


@st.composite
def mutated_missions(draw) -> str:
    """A real mission with a few spans deleted, duplicated or replaced by tokens."""
    text = draw(st.sampled_from(SEEDS))
    for _ in range(draw(st.integers(1, 4))):
        start = draw(st.integers(0, len(text)))
        end = min(len(text), start + draw(st.integers(0, 40)))
        edit = draw(st.sampled_from(["delete", "insert", "replace", "duplicate"]))
        token = draw(st.sampled_from(TOKENS))
        if edit == "delete":
            text = text[:start] + text[end:]
        elif edit == "insert":
            text = text[:start] + token + text[start:]
        elif edit == "replace":
            text = text[:start] + token + text[end:]
        else:
            text = text[:end] + text[start:end] + text[end:]
    return text


def _parse_and_check(text: str, world) -> tuple[Diagnostic, ...]:
    """Parse, check, build and check the state graph, compile when clean."""
    return check_source(text, "fuzz.mission", world=world).diagnostics


@settings(max_examples=1000, deadline=None, suppress_health_check=list(HealthCheck))
@given(text=mutated_missions())
def test_mutated_missions_only_give_diagnostics(text, bazar):
    """1,000 mutated missions: every problem is a located Diagnostic, nothing raises."""
    for diagnostic in _parse_and_check(text, bazar):
        assert isinstance(diagnostic, Diagnostic)
        assert diagnostic.code and diagnostic.message


@settings(max_examples=300, deadline=None, suppress_health_check=list(HealthCheck))
@given(text=st.lists(st.sampled_from(TOKENS + ["a", "x1", "_", "9", "\t"]), max_size=80)
       .map(" ".join))
def test_token_soup_only_gives_diagnostics(text, bazar):
    """Random sequences of the language's tokens never make the pipeline raise."""
    for diagnostic in _parse_and_check(text, bazar):
        assert isinstance(diagnostic, Diagnostic)
