"""``robocop-mission check``: output formats and exit codes."""

import argparse
import json
import subprocess
import sys
from pathlib import Path

import pytest

from robocop_dsl.cli import check_cmd

REPO = Path(__file__).resolve().parent.parent
INVALID = REPO / "tests" / "fixtures" / "invalid"
# The command as the entry point dispatches it: add_parser, then args.command(args).
HARNESS = ("import argparse, sys\n"
           "from robocop_dsl.cli import check_cmd\n"
           "parser = argparse.ArgumentParser(prog='robocop-mission')\n"
           "check_cmd.add_parser(parser.add_subparsers(dest='name', required=True))\n"
           "args = parser.parse_args(sys.argv[1:])\n"
           "sys.exit(args.command(args))\n")


def check(*argv: str) -> int:
    parser = argparse.ArgumentParser(prog="robocop-mission")
    check_cmd.add_parser(parser.add_subparsers(dest="name", required=True))
    try:
        args = parser.parse_args(["check", *argv])
    except SystemExit as exit_:
        return exit_.code
    return args.command(args)


def test_missions_are_ok(capsys):
    """Each clean file prints FILE: OK; exit 0."""
    files = sorted(str(p.relative_to(REPO)) for p in (REPO / "missions").glob("*.mission"))
    assert check(*[str(REPO / f) for f in files]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out == [f"{REPO / f}: OK" for f in files]


def test_errors_rendered_with_source_caret_and_hint(capsys):
    """Diagnostics as FILE:LINE:COL: error[CODE]: message, source, caret, hint; exit 1."""
    path = INVALID / "unknown_state.mission"
    assert check(str(path)) == 1
    assert capsys.readouterr().out == (
        f"{path}:28:26: error[unknown-state]: unknown state 'aproach'\n"
        " 28 |     when arms.reached -> aproach\n"
        "    |                          ^^^^^^^\n"
        "   = hint: did you mean 'approach'?\n\n"
        f"{path}:32:7: warning[unreachable-state]: state 'approach' cannot be reached "
        "from 'ready'\n"
        " 32 | state approach {\n"
        "    |       ^^^^^^^^\n"
        "   = hint: no clause leads to it: remove it or add a 'when ... ->' to it\n\n"
        f"{path}:43:7: warning[unreachable-state]: state 'done' cannot be reached from "
        "'ready'\n"
        " 43 | final done\n"
        "    |       ^^^^\n"
        "   = hint: no clause leads to it: remove it or add a 'when ... ->' to it\n\n"
        f"{path}: 1 error, 2 warnings\n")


def test_warnings_alone_exit_zero_unless_strict(capsys):
    """Warnings do not fail the check; --strict turns them into errors."""
    path = str(INVALID / "unreachable_state.mission")
    assert check(path) == 0
    assert capsys.readouterr().out.endswith(f"{path}: 1 warning\n")
    assert check(path, "--strict") == 1
    out = capsys.readouterr().out
    assert "error[unreachable-state]" in out and out.endswith(f"{path}: 1 error\n")


def test_json_format(capsys):
    """--format json: one entry per file with its diagnostics."""
    good, bad = REPO / "missions" / "pickup.mission", INVALID / "missing_arrow.mission"
    assert check(str(good), str(bad), "--format", "json") == 1
    report = json.loads(capsys.readouterr().out)
    assert [(r["file"], r["ok"]) for r in report] == [(str(good), True), (str(bad), False)]
    diagnostic = report[1]["diagnostics"][0]
    assert diagnostic["code"] == "missing-token"
    assert diagnostic["span"] == {"line": 28, "column": 23, "end_line": 28, "end_column": 31}
    assert diagnostic["hint"] == "a transition is written 'when CONDITION -> STATE'"


def test_github_format(capsys):
    """--format github: workflow commands that annotate the line."""
    path = INVALID / "unknown_unit.mission"
    assert check(str(path), "--format", "github") == 1
    assert capsys.readouterr().out == (
        f"::error file={path},line=7,col=26,endLine=7,endColumn=28,title=unknown-unit::"
        "unknown unit 'kg' (hint: units: m, cm, mm, rad, deg, s, ms, m/s, cm/s, mm/s, "
        "rad/s, deg/s, m/s^2, rad/s^2, deg/s^2, m/s^3, rad/s^3, deg/s^3, N, kN, mN, Nm, "
        "(m/s)/N, (cm/s)/N, (mm/s)/N)\n")


def test_usage_errors_exit_two(capsys):
    """A missing file, no file or a bad option is a usage error."""
    assert check("no/such.mission") == 2
    assert "no such file: no/such.mission" in capsys.readouterr().err
    assert check() == 2
    assert check(str(REPO / "missions" / "pickup.mission"), "--format", "xml") == 2


@pytest.mark.parametrize("command, name", [("check", "missions"), ("graph", "missions"),
                                           ("graph", "/dev/null"),
                                           ("sweep", "missions")])
def test_a_folder_or_a_device_is_not_a_file_to_read(command, name):
    """A folder or a device named as a mission or a campaign is said to be what it is
    (not a missing file), without a traceback."""
    done = subprocess.run([sys.executable, "-m", "robocop_dsl", command, name],
                          capture_output=True, text=True, cwd=REPO)
    assert done.returncode == 2
    assert "not a regular file" in done.stderr + done.stdout
    assert "no such file" not in done.stderr and "Traceback" not in done.stderr


@pytest.mark.parametrize("name, code", [("pickup.mission", 0), ("missing.mission", 2)])
def test_from_a_real_process(name, code):
    """Run as a process: exit code and output as a shell sees them."""
    path = REPO / "missions" / name
    done = subprocess.run([sys.executable, "-c", HARNESS, "check", str(path)],
                          capture_output=True, text=True, cwd=REPO)
    assert done.returncode == code
    if code == 0:
        assert done.stdout == f"{path}: OK\n"


def test_bad_file_from_a_real_process():
    """A broken mission exits 1 and prints every diagnostic."""
    path = INVALID / "several_syntax_errors.mission"
    done = subprocess.run([sys.executable, "-c", HARNESS, "check", str(path)],
                          capture_output=True, text=True, cwd=REPO)
    assert done.returncode == 1
    assert done.stdout.count("error[") == 4
    assert done.stderr == ""


@pytest.mark.parametrize("written, typed, reported", [
    ("approach_height], 2 mm, 20 s)", "approach_height, 2 mm, 20 s)",
     "60:69: error[missing-token]: missing ']' before name 'mm'"),
    ("enter { left_tool.target = goal }", "enter { left_tool.target = goal offset [0, 0, 1 }",
     "39:57: error[missing-token]: missing ']' before '}'"),
    ("let carry_height    = 15 cm", "let carry_height    = [15 cm",
     "9:27: error[missing-token]: missing ']' before name 'cm'"),
    ("state grasp: reach(pickup_point, 1 mm, 10 s) {",
     "state grasp: reach(pickup_point, 1 mm, 10 s {",
     "66:45: error[missing-token]: missing ')' before '{'"),
    ("let approach_height = 10 cm", "let approach_height = = 10 cm",
     "8:23: error[syntax-error]: unexpected '='"),
    ("state goto_initial_pose {", "stat goto_initial_pose {",
     "49:1: error[syntax-error]: unexpected name 'stat'"),
])
def test_a_statement_that_does_not_parse_gets_its_syntax_error_alone(
        tmp_path, capsys, written, typed, reported):
    """An unclosed '(' or '[' (or any syntax error) is the one error of its statement:
    the checker says nothing about the statement's partial call or vector, nor about
    the uses of a name it declares (without it: a missing argument, a wrong dimension,
    an unknown body, 'not a number' where the name is used; a declaration whose keyword
    is misspelt declares its name all the same)."""
    pickup = (REPO / "missions" / "pickup.mission").read_text()
    assert written in pickup
    path = tmp_path / "pickup.mission"
    path.write_text(pickup.replace(written, typed).replace('"bazar/', f'"{REPO}/robots/bazar/'))
    assert check(str(path), "--format", "json") == 1
    [report] = json.loads(capsys.readouterr().out)
    assert [f"{d['span']['line']}:{d['span']['column']}: {d['severity']}[{d['code']}]: "
            f"{d['message']}" for d in report["diagnostics"]] == [reported]


def test_a_misspelt_first_state_is_the_one_error_and_names_the_keyword(tmp_path, capsys):
    """The first state's keyword misspelt: its block does not parse, so the final state
    is the first that did; that the mission would start in it follows from the typo and
    is not reported. The hint names the keyword meant."""
    path = tmp_path / "typo.mission"
    path.write_text(f'mission typo "x"\n\nworld "{REPO}/robots/bazar/sophia.yaml"\n\n'
                    'task arms: joint_position(bazar_arms) {\n    priority = 1\n}\n\n'
                    'stat first {\n    enter { enable arms }\n    when arms.reached -> done\n}\n'
                    '\nfinal done\n')
    assert check(str(path), "--format", "json") == 1
    [report] = json.loads(capsys.readouterr().out)
    assert [(d["span"]["line"], d["code"], d["message"], d["hint"])
            for d in report["diagnostics"]] == [
        (9, "syntax-error", "unexpected name 'stat'", "did you mean 'state'?")]


def test_a_declaration_that_recovery_mended_is_checked_like_any_other(tmp_path, capsys):
    """The header of state grasp lacks its ')': recovery mends it, so the state exists,
    and enabling it as if it were a task is still reported with the syntax error."""
    pickup = (REPO / "missions" / "pickup.mission").read_text()
    text = pickup.replace("state grasp: reach(pickup_point, 1 mm, 10 s) {",
                          "state grasp: reach(pickup_point, 1 mm, 10 s {")
    text = text.replace("        disable left_tool\n", "        disable left_tool\n"
                        "        enable grasp\n", 1)
    path = tmp_path / "pickup.mission"
    path.write_text(text.replace('"bazar/', f'"{REPO}/robots/bazar/'))
    assert check(str(path), "--format", "json") == 1
    [report] = json.loads(capsys.readouterr().out)
    assert [(d["code"], d["message"]) for d in report["diagnostics"]] == [
        ("missing-token", "missing ')' before '{'"),
        ("unknown-task", "unknown task or constraint 'grasp'")]


def test_a_library_statement_that_does_not_parse_gets_its_syntax_error_alone(tmp_path, capsys):
    """A 'let' of an imported library left with an open '[': its importer sees that
    syntax error, not the library's uses of the constant as 'not a number'."""
    for name in ("two_parts.mission", "bazar_common.mission"):
        text = (REPO / "missions" / name).read_text()
        text = text.replace("let carry_height    = 15 cm", "let carry_height    = [15 cm")
        (tmp_path / name).write_text(text.replace('"bazar/', f'"{REPO}/robots/bazar/'))
    assert check(str(tmp_path / "two_parts.mission"), "--format", "json") == 1
    [report] = json.loads(capsys.readouterr().out)
    assert [(Path(d["file"]).name, d["code"], d["message"]) for d in report["diagnostics"]] == [
        ("bazar_common.mission", "missing-token", "missing ']' before name 'cm'")]


@pytest.mark.parametrize("change, errors", [
    ("", 1),
    ("    max_position = [1, 1, 1, -2, 1, 2, 1] rad\n    enabled = false\n", 0),
    ("state s {\n    enter { disable low }\n", 0),
    ("    max_position = [1, 1, 1, -2, 1, 2, 1] rad\n    enabled = false\n"
     "}\nstate s {\n    enter { enable low }\n", 1),
])
def test_two_joint_ranges_apart_are_an_error_only_when_both_start_enabled(tmp_path, capsys,
                                                                          change, errors):
    """Two ``joint_kinematic`` ranges that leave a joint no position refuse the first
    cycle when both are enabled then; enabled apart, they are not an error."""
    text = (INVALID / "joint_ranges_apart.mission").read_text()
    if change.startswith("state"):
        text = text.replace("state s {\n", change)
    elif "enter" in change:
        declared, entered = change.split("}\n", 1)
        text = text.replace("    max_position = [1, 1, 1, -2, 1, 2, 1] rad\n", declared)
        text = text.replace("state s {\n", entered)
    elif change:
        text = text.replace("    max_position = [1, 1, 1, -2, 1, 2, 1] rad\n", change)
    (tmp_path / "m.mission").write_text(text)
    assert check(str(tmp_path / "m.mission")) == (1 if errors else 0)
    assert capsys.readouterr().out.count("error[inverted-limits]") == errors
