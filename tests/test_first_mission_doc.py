"""docs/first_mission.md works as written: its files, written where a reader writes
them, and its commands, run one after the other as a reader runs them."""

import re
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
PAGE = REPO / "docs" / "first_mission.md"
BLOCK = re.compile(r"^```(\w+)([^\n]*)\n(.*?)^```", re.MULTILINE | re.DOTALL)


def blocks():
    """``(language, file name or None, text)`` of each fenced block, in page order."""
    for language, info, text in BLOCK.findall(PAGE.read_text()):
        named = re.search(r"file=(\S+)", info)
        yield language, named.group(1) if named else None, text


def test_every_command_of_the_page_works(tmp_path):
    files = [(name, text) for _, name, text in blocks() if name]
    assert [name for name, _ in files] == ["ur5_on_table.yaml", "reach.mission",
                                           "ur5_physics.yaml"]
    for name, text in files:
        (tmp_path / name).write_text(text)
    commands = [line for language, name, text in blocks() if language == "bash"
                for line in text.splitlines() if line.startswith("robocop-mission ")]
    assert len(commands) >= 5
    outputs = {}
    for command in commands:
        arguments = command.split()[1:]
        done = subprocess.run([sys.executable, "-m", "robocop_dsl", *arguments],
                              capture_output=True, text=True, cwd=tmp_path, check=False)
        assert done.returncode == 0, f"{command}\n{done.stdout}\n{done.stderr}"
        outputs[command] = done.stdout
    world = outputs["robocop-mission world ur5_on_table.yaml"]
    page = PAGE.read_text()
    for body in ("ur5_base_link", "ur5_tool0", "goal_point"):
        position = re.search(rf"^\s+{body}\s.*?\[([-\d., ]+)\]", world, re.MULTILINE)
        assert position is not None, body
        assert f"[{position.group(1)}]" in page or position.group(1).split(", ")[2] in page
    assert "reach.mission: OK" in outputs["robocop-mission check reach.mission"]
    run = outputs["robocop-mission run reach.mission --log reach_log"]
    assert "outcome: success" in run and "tasks at the end" in run
    for figure in ("joint_positions.png", "velocity_commands.png", "task_errors.png"):
        assert (tmp_path / "reach_log" / figure).is_file()
    assert "outcome: success" in outputs[
        "robocop-mission run reach.mission --world ur5_physics.yaml"]
    assert "<mujoco" in (tmp_path / "ur5.xml").read_text()
