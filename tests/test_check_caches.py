"""What ``check`` keeps between runs: the parser's tables and the world's collision facts,
each in the user's private cache folder, named after what it depends on."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import lark
import pytest

from robocop_dsl.compile import WorldCache, check_file
from robocop_dsl.lang.parser import build_parser, mission_grammar
from robocop_dsl.resources import GRAMMAR_DIR, ROBOTS_DIR
from robocop_dsl.world import load_world
from robocop_dsl.world.collision_facts import CollisionFacts, fingerprint

REPO = GRAMMAR_DIR.parent
PICKUP = REPO / "missions" / "pickup.mission"
AT_START = REPO / "tests" / "fixtures" / "invalid" / "collision_at_start.mission"
GRAMMAR = (GRAMMAR_DIR / "mission.lark").read_text(encoding="utf-8")
TRANSITION = 'mission m "x"\nstate a {\n    when elapsed > 1 s {arrow} done\n}\nfinal done\n'


def check_cli(*argv: str, cache_home) -> subprocess.CompletedProcess:
    """``robocop-mission check ARGV`` with ``$XDG_CACHE_HOME`` at ``cache_home``."""
    return subprocess.run([sys.executable, "-m", "robocop_dsl", "check", *argv],
                          capture_output=True, text=True,
                          env={**os.environ, "XDG_CACHE_HOME": str(cache_home)})


@pytest.fixture
def loads(monkeypatch):
    """How many times lark loaded a parser from a cache file."""
    count = [0]
    original = lark.Lark._load

    def counted(self, *args, **kwargs):
        count[0] += 1
        return original(self, *args, **kwargs)

    monkeypatch.setattr(lark.Lark, "_load", counted)
    return count


def test_the_second_parser_is_loaded_from_the_cache_file(tmp_path, monkeypatch, loads):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    build_parser(GRAMMAR)
    [cached] = (tmp_path / "robocop-mission").iterdir()
    written = cached.stat().st_mtime_ns
    assert loads[0] == 0
    parser = build_parser(GRAMMAR)
    assert loads[0] == 1
    assert cached.stat().st_mtime_ns == written
    assert parser.parse(TRANSITION.replace("{arrow}", "->")).data == "start"


def test_a_changed_grammar_never_meets_the_old_tables(tmp_path, monkeypatch, loads):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    changed = GRAMMAR.replace('_ARROW: "->"', '_ARROW: "=>"')
    assert changed != GRAMMAR
    build_parser(GRAMMAR)
    parser = build_parser(changed)
    assert loads[0] == 0
    assert len(list((tmp_path / "robocop-mission").iterdir())) == 2
    assert parser.parse(TRANSITION.replace("{arrow}", "=>")).data == "start"
    with pytest.raises(lark.exceptions.UnexpectedInput):
        parser.parse(TRANSITION.replace("{arrow}", "->"))
    assert build_parser(changed).parse(TRANSITION.replace("{arrow}", "=>")).data == "start"
    assert loads[0] == 1


@pytest.mark.parametrize("cache_home", ["/dev/null/cache", "file"])
def test_a_cache_folder_that_cannot_be_made_only_costs_time(tmp_path, cache_home):
    if cache_home == "file":
        cache_home = tmp_path / "file"
        cache_home.write_text("not a folder")
    for _ in range(2):
        done = check_cli(str(PICKUP), cache_home=cache_home)
        assert (done.returncode, done.stderr) == (0, "")
        assert done.stdout == f"{PICKUP}: OK\n"


def test_a_folder_that_cannot_be_written_only_costs_time(tmp_path):
    """A private folder whose files cannot be created (here: their names are taken by
    folders) is no error; what ``check`` reports is the same."""
    warm = check_cli(str(AT_START), cache_home=tmp_path / "warm")
    folder = tmp_path / "blocked" / "robocop-mission"
    folder.mkdir(parents=True, mode=0o700)
    for name in os.listdir(tmp_path / "warm" / "robocop-mission"):
        (folder / name).mkdir()
    blocked = check_cli(str(AT_START), cache_home=tmp_path / "blocked")
    assert (blocked.returncode, blocked.stdout, blocked.stderr) == \
        (warm.returncode, warm.stdout, "")


def test_collision_facts_come_back_from_the_cache_file(tmp_path, monkeypatch):
    """The warning of a pair close at the start is the same measured and read back, and
    the second check builds no collision geometry."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    cold = check_file(AT_START, cache=WorldCache(), compiled=False).diagnostics
    [facts] = (tmp_path / "robocop-mission").glob("world-collisions-*.json")
    stored = json.loads(facts.read_text())
    assert "bazar_left_link_1" in stored["bodies"]
    [(key, closest)] = stored["closest"].items()
    assert key == "bazar_left_arm\tworkbench\t0.45"
    assert ["bazar_left_link_1", "workbench"] in [pair[:2] for pair in closest]

    def refused(*args, **kwargs):
        raise AssertionError("collision geometry built again")

    monkeypatch.setattr("robocop_dsl.world.collisions.CollisionGeometry", refused)
    monkeypatch.setattr("robocop_dsl.world.collision_facts._closest", refused)
    warm = check_file(AT_START, cache=WorldCache(), compiled=False).diagnostics
    assert warm == cold
    [warning] = [d for d in warm if d.code == "collision-at-start"]
    assert warning.message == ("'bazar_left_link_1' and 'workbench' are 39.6 cm apart in "
                               "the initial posture, closer than min_distance (45 cm)")


def test_the_facts_of_another_world_are_never_read(tmp_path, monkeypatch):
    """A changed initial posture is another world: its facts are measured anew."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    world = load_world(ROBOTS_DIR / "bazar" / "sophia.yaml")
    near = CollisionFacts(world).closest_at_start("bazar_left_arm", "workbench", 0.45)
    assert [pair[:2] for pair in near] == [("bazar_left_link_1", "workbench")]
    assert near[0][2] == pytest.approx(0.396, abs=1e-3)
    moved = load_world(ROBOTS_DIR / "bazar" / "sophia.yaml")
    moved._assembly.initial["bazar_left_joint_1"] = moved._assembly.initial[
        "bazar_left_joint_1"] + 1.0
    assert fingerprint(moved) != fingerprint(world)
    again = CollisionFacts(moved).closest_at_start("bazar_left_arm", "workbench", 0.45)
    assert again != near
    assert len(list((tmp_path / "robocop-mission").glob("world-collisions-*.json"))) == 2


def test_the_check_command_needs_neither_pinocchio_nor_coal_once_warm(tmp_path):
    check_cli(str(PICKUP), cache_home=tmp_path)
    script = ("import sys\nfrom robocop_dsl.cli.main import main\n"
              f"code = main(['check', {str(PICKUP)!r}])\n"
              "print(code, sorted(m for m in ('pinocchio', 'coal', 'matplotlib', 'pygls')"
              " if m in sys.modules))\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          env={**os.environ, "XDG_CACHE_HOME": str(tmp_path)})
    assert done.stdout.splitlines()[-1] == "0 []", done.stdout + done.stderr


def test_the_grammar_in_use_is_the_shipped_one():
    assert mission_grammar().source_grammar == GRAMMAR


@pytest.mark.parametrize("damage", ["{", "[]", '{"bodies": 3}', '{"closest": {"k": [[1]]}}'])
def test_a_damaged_facts_file_is_measured_again(tmp_path, monkeypatch, damage):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    cold = check_file(AT_START, cache=WorldCache(), compiled=False).diagnostics
    [facts] = (tmp_path / "robocop-mission").glob("world-collisions-*.json")
    facts.write_text(damage)
    assert check_file(AT_START, cache=WorldCache(), compiled=False).diagnostics == cold
    assert json.loads(facts.read_text())["bodies"]
