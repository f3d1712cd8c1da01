"""``check`` on untrusted input (missions from a pull request): files it must not read,
input built to exhaust memory or the stack, odd line breaks and bytes, GitHub
annotations, the parser cache, and checking time on large missions."""

from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from robocop_dsl.compile import WorldCache, check_file, check_source
from robocop_dsl.check import enabled  # after compile, which imports check first
from robocop_dsl.lang.parser import MAX_NESTING, private_cache
from robocop_dsl.resources import ROBOTS_DIR
from robocop_dsl.sources import MAX_SOURCE_BYTES
from robocop_dsl.world.yaml_source import MAX_DEPTH

PANDA = ROBOTS_DIR / "panda" / "panda_on_table.yaml"
BAZAR = ROBOTS_DIR / "bazar" / "sophia.yaml"
SECRET = "BEGIN-PRIVATE-KEY-c2VjcmV0"
CACHE = WorldCache()


def mission(world: str = str(PANDA), condition: str = "elapsed > 1 s") -> str:
    return (f'mission m "hostile"\nworld "{world}"\nstate a {{\n'
            f'    when {condition} -> done\n}}\nfinal done\n')


def check_cli(*argv: str, stdin: str = "", env: dict | None = None):
    """``robocop-mission check ARGV`` as a user runs it."""
    return subprocess.run([sys.executable, "-m", "robocop_dsl", "check", *argv],
                          input=stdin, capture_output=True, text=True,
                          env={**os.environ, **(env or {})})


def only_located(done) -> list[dict]:
    """The JSON report's diagnostics, after checking nothing went wrong with the run."""
    assert "Traceback" not in done.stderr
    reports = json.loads(done.stdout)
    found = [d for report in reports for d in report["diagnostics"]]
    assert all(d["span"] and d["span"]["line"] >= 1 and d["span"]["column"] >= 1
               for d in found), found
    return found


# ---- files that are not sources are never read ------------------------------------

@pytest.fixture
def secret(tmp_path) -> Path:
    path = tmp_path / "id_ed25519"
    path.write_text(f"-----{SECRET}-----\nmodels: []\n")
    return path


@pytest.mark.parametrize("fmt", ["text", "json", "github"])
def test_a_secret_file_named_as_world_is_never_quoted(tmp_path, secret, fmt):
    (tmp_path / "m.mission").write_text(mission(str(secret)))
    done = check_cli("--format", fmt, str(tmp_path / "m.mission"))
    assert done.returncode == 1
    assert SECRET not in done.stdout + done.stderr
    assert "unreadable-file" in done.stdout and "not a YAML file" in done.stdout


def test_a_link_named_yaml_to_a_secret_is_refused(tmp_path, secret):
    (tmp_path / "world.yaml").symlink_to(secret)
    (tmp_path / "m.mission").write_text(mission("world.yaml"))
    done = check_cli("--format", "json", str(tmp_path / "m.mission"))
    [diagnostic] = [d for d in only_located(done) if d["code"] == "unreadable-file"]
    assert SECRET not in done.stdout and diagnostic["span"]["line"] == 2


@pytest.mark.parametrize("device", ["/dev/zero", "/dev/stdin", "/etc/passwd"])
def test_devices_and_system_files_are_not_read(tmp_path, device):
    (tmp_path / "m.mission").write_text(mission(device))
    done = check_cli("--format", "json", str(tmp_path / "m.mission"), stdin=SECRET)
    assert done.returncode == 1 and SECRET not in done.stdout
    codes = [d["code"] for d in only_located(done)]
    assert codes == ["unreadable-file"]
    assert "root:" not in done.stdout


@pytest.mark.parametrize("entry, name", [("path: /bin/ls", "URDF '/bin/ls'"),
                                         ("path: robocop/point.urdf\n    srdf: /etc/passwd",
                                          "SRDF '/etc/passwd'")])
def test_a_model_file_that_is_not_one_is_refused_where_the_world_names_it(
        tmp_path, entry, name):
    """A world's model or SRDF that cannot be read as one is an error at the line of
    the world file that names it, and nothing of it is quoted."""
    (tmp_path / "world.yaml").write_text(f"models:\n  - include: {BAZAR}\n"
                                         f"  - namespace: p1\n    {entry}\n")
    (tmp_path / "m.mission").write_text(mission("world.yaml"))
    done = check_cli("--format", "json", str(tmp_path / "m.mission"))
    [bad] = [d for d in only_located(done) if d["code"] == "unreadable-file"]
    assert bad["file"] == str(tmp_path / "world.yaml") and bad["span"]["line"] >= 4
    assert bad["message"].startswith(f"cannot read {name}:")
    assert "root:" not in done.stdout and "ELF" not in done.stdout


def test_a_fifo_named_world_yaml_is_refused_without_opening_it(tmp_path):
    os.mkfifo(tmp_path / "world.yaml")
    (tmp_path / "m.mission").write_text(mission("world.yaml"))
    result = check_file(tmp_path / "m.mission")
    [diagnostic] = result.diagnostics
    assert diagnostic.code == "unreadable-file" and "not a regular file" in diagnostic.message


def test_a_world_over_the_size_limit_is_refused(tmp_path):
    with open(tmp_path / "world.yaml", "wb") as huge:
        huge.truncate(MAX_SOURCE_BYTES + 1)
    (tmp_path / "m.mission").write_text(mission("world.yaml"))
    [diagnostic] = check_file(tmp_path / "m.mission").diagnostics
    assert diagnostic.code == "unreadable-file" and "larger than" in diagnostic.message


def test_a_mission_named_otherwise_is_not_read(secret):
    done = check_cli("--format", "json", str(secret))
    assert done.returncode == 1 and SECRET not in done.stdout
    assert [d["code"] for d in only_located(done)] == ["unreadable-file"]


def test_an_import_of_a_secret_is_refused(tmp_path, secret):
    (tmp_path / "m.mission").write_text(f'import "{secret}"\n' + mission())
    result = check_file(tmp_path / "m.mission")
    [diagnostic] = result.diagnostics
    assert diagnostic.code == "import-not-found" and diagnostic.span.line == 1
    assert SECRET not in diagnostic.render()


# ---- YAML built to exhaust memory or the stack --------------------------------------

BOMB = "".join(f'{a}: &{a} [{", ".join([f"*{p}"] * 9)}]\n'
               for p, a in zip("abcdefgh", "bcdefghi"))


def test_a_yaml_alias_bomb_is_a_located_error(tmp_path):
    (tmp_path / "world.yaml").write_text('a: &a ["lol","lol","lol","lol","lol","lol","lol",'
                                         '"lol","lol"]\n' + BOMB + "models: *i\n")
    (tmp_path / "m.mission").write_text(mission("world.yaml"))
    assert (tmp_path / "world.yaml").stat().st_size < 600
    found = only_located(check_cli("--format", "json", str(tmp_path / "m.mission")))
    [bomb] = [d for d in found if d["file"].endswith("world.yaml")]
    assert bomb["code"] == "yaml-syntax" and "expand to more than" in bomb["message"]
    assert bomb["span"]["line"] == 6


def test_yaml_nested_5000_deep_is_a_located_error(tmp_path):
    (tmp_path / "world.yaml").write_text("models:\n  - " + "[" * 5000 + "]" * 5000 + "\n")
    (tmp_path / "m.mission").write_text(mission("world.yaml"))
    found = only_located(check_cli("--format", "json", str(tmp_path / "m.mission")))
    [deep] = [d for d in found if d["file"].endswith("world.yaml")]
    assert deep["code"] == "yaml-syntax" and f"more than {MAX_DEPTH}" in deep["message"]
    assert (deep["span"]["line"], deep["span"]["column"]) == (2, 3 + MAX_DEPTH)


def test_a_yaml_alias_into_itself_is_a_located_error(tmp_path):
    (tmp_path / "world.yaml").write_text("models: &m [*m]\n")
    (tmp_path / "m.mission").write_text(mission("world.yaml"))
    found = only_located(check_cli("--format", "json", str(tmp_path / "m.mission")))
    assert any("contains it" in d["message"] for d in found)


def test_a_key_set_twice_is_a_located_error(tmp_path):
    """YAML keeps the last of two values of one key without a word: a world that sets
    an initial posture twice is an error at the second."""
    (tmp_path / "world.yaml").write_text(
        f"models:\n  - include: {BAZAR}\ninitial:\n  bazar_arms: [0, 0.2]\n"
        "  bazar_arms: [0, 0.3]\n")
    (tmp_path / "m.mission").write_text(mission("world.yaml"))
    found = only_located(check_cli("--format", "json", str(tmp_path / "m.mission")))
    [bad] = [d for d in found if d["file"].endswith("world.yaml")]
    assert bad["code"] == "yaml-syntax" and bad["span"]["line"] == 5
    assert "'bazar_arms' is set twice (first at line 4)" in bad["message"]


@pytest.mark.parametrize("text, problem", [
    ("models:\n  - ? [a]\n    : 1\n", "a key must be a single value"),
    ("models:\n  - path: !!binary aGk=\n", "'binary' has no meaning here"),
    ("models:\n  - path: 1" + "0" * 5000 + "\n", "as an integer"),
    ("models:\n  - path: !!float .nanx\n", "as a number")])
def test_yaml_values_python_cannot_hold_are_located_errors(tmp_path, text, problem):
    (tmp_path / "world.yaml").write_text(text)
    (tmp_path / "m.mission").write_text(mission("world.yaml"))
    [bad] = [d for d in check_file(tmp_path / "m.mission").diagnostics
             if d.file.endswith("world.yaml")]
    assert bad.code == "yaml-syntax" and problem in bad.message and bad.span.line == 2


@pytest.mark.parametrize("entry, problem, line", [
    ("  - path: robocop/point.urdf\n    namespace: p1\n"
     "    joint: {position: {angular: [.nan, 0, 0]}}\n",
     "'angular' must be 3 finite numbers", 5),
    ("  - path: robocop/point.urdf\n    namespace: p1\n"
     "    joint: {position: {linear: [.inf, 0, 0]}}\n",
     "'linear' must be 3 finite numbers", 5),
    ("initial:\n  bazar_arms: [1e308, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]\n",
     "'bazar_arms' must be a list of finite numbers", 4),
    ("initial:\n  bazar_arms: [.nan, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]\n",
     "'bazar_arms' must be a list of finite numbers", 4)])
def test_numbers_a_world_cannot_place_a_joint_at_are_one_located_error(
        tmp_path, entry, problem, line):
    """NaN, infinity, or a number YAML read as text, where the world places or starts a
    joint: one error at its line, in ``world`` as in ``check``."""
    world = tmp_path / "world.yaml"
    world.write_text(f"models:\n  - include: {BAZAR}\n" + entry)
    (tmp_path / "m.mission").write_text(mission("world.yaml"))
    found = only_located(check_cli("--format", "json", str(tmp_path / "m.mission")))
    [bad] = [d for d in found if d["file"].endswith("world.yaml")]
    assert (bad["code"], bad["message"], bad["span"]["line"]) == ("invalid-entry", problem, line)
    shown = subprocess.run([sys.executable, "-m", "robocop_dsl", "world", str(world)],
                           capture_output=True, text=True)
    assert shown.returncode == 1 and "Traceback" not in shown.stderr
    assert f"world.yaml:{line}:" in shown.stdout + shown.stderr and problem in shown.stdout + shown.stderr


# ---- no recursion limit reachable from a mission ------------------------------------

def _ands(depth: int) -> str:
    condition = "elapsed > 1 s"
    for _ in range(depth):
        condition = f"(elapsed > 2 s and {condition})"
    return condition


def _nested_states(depth: int) -> str:
    opened = "".join(f"state s{i} {{\n" for i in range(depth))
    return (f'mission m "deep"\nworld "{PANDA}"\n{opened}when elapsed > 1 s -> done\n'
            + "}\n" * depth + "final done\n")


DEEP = {"nots": mission(condition="not " * 500 + "elapsed > 1 s"),
        "ands": mission(condition=_ands(300)),
        "states": _nested_states(300)}


def test_deep_missions_are_located_errors_and_a_multi_file_check_goes_on(tmp_path):
    files = []
    for name, text in DEEP.items():
        files.append(tmp_path / f"{name}.mission")
        files[-1].write_text(text)
    files.append(tmp_path / "fine.mission")
    files[-1].write_text(mission())
    done = check_cli("--format", "json", *map(str, files))
    assert done.returncode == 1
    reports = json.loads(done.stdout)
    assert [r["file"] for r in reports] == list(map(str, files))
    assert [r["ok"] for r in reports] == [False, False, False, True]
    nested = [d for d in only_located(done) if "nested more than" in d["message"]]
    assert [(d["file"], d["span"]["line"]) for d in nested] == [
        (str(files[0]), 4), (str(files[1]), 4), (str(files[2]), 3 + MAX_NESTING // 2 - 1)]


@pytest.mark.parametrize("text", [mission(condition="not " * 190 + "elapsed > 1 s"),
                                  mission(condition=_ands(190)), _nested_states(64),
                                  mission(condition="elapsed > " + " + ".join(["1 ms"] * 190))])
def test_missions_just_within_the_nesting_bound_check_and_compile(text):
    result = check_source(text, "deep.mission", cache=CACHE)
    assert not any("nested" in d.message for d in result.diagnostics)
    assert result.world is not None


def test_a_statement_nested_too_deep_leaves_the_rest_of_the_file_checked():
    """The statement too deep is refused; the others are read and checked (the whole
    file used to be dropped, with errors about a missing header, world and states)."""
    text = mission(condition="elapsed > 1 s and nowhere.reached") + \
        f"let deep = {'-' * 300}1 m\n"
    result = check_source(text, "deep.mission", cache=CACHE)
    found = [(d.code, d.span.line) for d in result.diagnostics]
    assert ("syntax-error", 7) in found
    assert any(code.startswith("unknown") and line == 4 for code, line in found)
    assert not any(d.code == "missing-declaration" for d in result.diagnostics)


def test_a_256_character_world_name_is_a_located_error(tmp_path):
    (tmp_path / "m.mission").write_text(mission("w" * 251 + ".yaml"))
    [diagnostic] = check_file(tmp_path / "m.mission").diagnostics
    assert (diagnostic.code, diagnostic.span.line) == ("world-not-found", 2)


@pytest.mark.parametrize("name", ["not " * 200 + "../composite.mission",
                                  "a/" * 3000 + "b.mission"])
def test_an_import_name_the_system_refuses_is_a_located_error(tmp_path, name):
    """An import whose path is too long for the system (a name over 255 bytes, a path
    over 4096) is reported where it is written, with no traceback."""
    text = mission().replace('state a {', f'import "{name}"\nstate a {{')
    (tmp_path / "m.mission").write_text(text)
    done = check_cli(str(tmp_path / "m.mission"), "--format", "json")
    [diagnostic] = only_located(done)
    assert (diagnostic["code"], diagnostic["span"]["line"]) == ("import-not-found", 3)
    assert done.returncode == 1


# ---- encodings ----------------------------------------------------------------------

def _latin1_world(tmp_path, declared: bool) -> Path:
    table = (ROBOTS_DIR / "panda" / "table.urdf").read_text()
    declaration = '<?xml version="1.0" encoding="ISO-8859-1"?>' if declared else \
        '<?xml version="1.0"?>'
    table = table.replace('<?xml version="1.0"?>', declaration + "\n<!-- Tisch für -->")
    (tmp_path / "table.urdf").write_bytes(table.encode("latin-1"))
    (tmp_path / "world.yaml").write_text("models:\n  - path: table.urdf\n")
    return tmp_path / "world.yaml"


def test_a_latin1_urdf_that_says_so_loads(tmp_path):
    from robocop_dsl.world import load_world
    world = load_world(_latin1_world(tmp_path, declared=True))
    assert world.has_body("table")


def test_a_latin1_urdf_that_does_not_say_so_is_located_at_the_byte(tmp_path):
    (tmp_path / "m.mission").write_text(mission(str(_latin1_world(tmp_path, False))))
    found = [d for d in check_file(tmp_path / "m.mission").diagnostics
             if d.code == "unreadable-file"]
    [bad] = found
    assert (bad.file, bad.span.line, bad.span.column) == (str(tmp_path / "table.urdf"), 2, 13)
    assert "0xfc" in bad.message and bad.source_line == "<!-- Tisch f\ufffdr -->"


def test_a_mission_not_in_utf8_is_located_at_the_byte(tmp_path):
    (tmp_path / "m.mission").write_bytes(mission().replace("hostile", "hostil\xe9")
                                         .encode("latin-1"))
    [diagnostic] = check_file(tmp_path / "m.mission").diagnostics
    assert diagnostic.code == "unreadable-file"
    assert (diagnostic.span.line, diagnostic.span.column) == (1, 18)
    assert "offset 17" in diagnostic.message



def test_a_byte_not_in_utf8_after_a_lone_carriage_return_is_on_the_next_line(tmp_path):
    """A lone '\\r' ends a mission's line there too, as in an editor."""
    (tmp_path / "m.mission").write_bytes(b"mission m\r\xffworld \"w.yaml\"\n")
    [diagnostic] = check_file(tmp_path / "m.mission").diagnostics
    assert (diagnostic.span.line, diagnostic.span.column) == (2, 1)
    assert diagnostic.source_line.endswith('world "w.yaml"')


# ---- lines counted as the parsers count them ----------------------------------------

@pytest.mark.parametrize("odd, line", [("\f", 5), ("\v", 5), ("\u2028", 5), ("\r", 6),
                                       ("\x85", 5), ("\x1c", 5)])
def test_quoted_mission_lines_follow_the_lexer(odd, line):
    """Only a line feed or a carriage return (alone, as editors count it) ends a line."""
    text = (f'mission m "x"\n# a comment{odd}with an odd break\nworld "{PANDA}"\n'
            "state a {\n    when elapsed > 1 s -> nowhere\n}\nfinal done\n")
    result = check_source(text, "odd.mission", cache=CACHE)
    [diagnostic] = [d for d in result.diagnostics if d.code == "unknown-state"]
    assert diagnostic.span.line == line
    assert diagnostic.source_line == "    when elapsed > 1 s -> nowhere"
    quoted = diagnostic.render().splitlines()
    assert quoted[1] == f" {line} |     when elapsed > 1 s -> nowhere"
    assert quoted[2].index("^") == quoted[1].index("nowhere")


def test_a_yaml_character_not_allowed_is_located(tmp_path):
    (tmp_path / "world.yaml").write_text("models:\n  - path: a\fb.urdf\n")
    (tmp_path / "m.mission").write_text(mission("world.yaml"))
    [bad] = [d for d in check_file(tmp_path / "m.mission").diagnostics
             if d.file.endswith("world.yaml")]
    assert (bad.code, bad.span.line, bad.span.column) == ("yaml-syntax", 2, 12)
    assert bad.render().splitlines()[1] == " 2 |   - path: a\ufffdb.urdf"


def test_github_properties_are_escaped(tmp_path):
    path = tmp_path / "a,b:c%d.mission"
    path.write_text(mission(condition="elapsed > 1 s and"))
    done = check_cli("--format", "github", str(path))
    line = done.stdout.splitlines()[0]
    properties, message = line.split("::")[1:]
    escaped = str(path).replace("%", "%25").replace(":", "%3A").replace(",", "%2C")
    assert properties.startswith(f"error file={escaped},line=")
    assert properties.count(",") == 5 and properties.count(":") == 0


# ---- the parser cache is no pickle in a shared folder -------------------------------

def test_the_parser_cache_is_kept_in_the_private_cache_folder(tmp_path):
    shared, private = tmp_path / "tmp", tmp_path / "cache"
    shared.mkdir()
    (tmp_path / "m.mission").write_text(mission())
    env = {"TMPDIR": str(shared), "XDG_CACHE_HOME": str(private)}
    for _ in range(2):
        assert check_cli(str(tmp_path / "m.mission"), env=env).returncode == 0
    assert list(shared.iterdir()) == []
    folder = private / "robocop-mission"
    [cached] = folder.glob("mission-grammar-*")
    assert not folder.stat().st_mode & 0o022 and not cached.stat().st_mode & 0o022
    assert cached.stat().st_uid == os.getuid()


def test_no_cache_when_others_may_write_the_cache_folder(tmp_path, monkeypatch):
    folder = tmp_path / "robocop-mission"
    folder.mkdir()
    folder.chmod(stat.S_IRWXU | stat.S_IRWXG | stat.S_IRWXO)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert private_cache("grammar") is False
    folder.chmod(stat.S_IRWXU)
    assert private_cache("grammar").startswith(str(folder))
    planted = Path(private_cache("grammar"))
    planted.symlink_to(tmp_path / "elsewhere")
    assert private_cache("grammar") is False


# ---- large missions -----------------------------------------------------------------

def _mesh(states: int) -> str:
    lines = ['mission mesh "x"', f'world "{PANDA}"', "start s0"]
    for i in range(states):
        body = [f"    when elapsed > {j + 1} s -> s{(i + j + 1) % states}"
                for j in range(states - 1)] + [f"    when elapsed > {states} s -> done"]
        lines.append(f"state s{i} {{\n" + "\n".join(body) + "\n}")
    return "\n".join(lines + ["final done"]) + "\n"


@pytest.mark.parametrize("states", [20, 60])
def test_what_may_be_enabled_visits_each_state_once(monkeypatch, states):
    """Each state of N states x N clauses (and the final one) is visited once, not once
    per clause into it."""
    visits = []
    original = enabled._apply
    monkeypatch.setattr(enabled, "_apply", lambda *a: visits.append(a) or original(*a))
    result = check_source(_mesh(states), "mesh.mission", cache=CACHE)
    assert result.mission is not None
    assert len(visits) == 2 * (states + 1)


def test_includes_are_refused_or_not_found_on_their_own_line(tmp_path):
    """A world's `include:` of a file that is no world, or of a name too long for the
    file system, is reported on the include's line; the file is never quoted."""
    from robocop_dsl.diagnostics import DiagnosticError
    from robocop_dsl.world import load_world

    world = tmp_path / "w.yaml"
    world.write_text("models:\n  - include: /etc/passwd\n  - include: " + "x" * 300
                     + ".yaml\n")
    with pytest.raises(DiagnosticError) as raised:
        load_world(world)
    found = [(d.code, d.span.line, d.span.column) for d in raised.value.diagnostics]
    assert found == [("unreadable-file", 2, 14), ("world-not-found", 3, 14)]
    assert "root:" not in str(raised.value)
