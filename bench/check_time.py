"""Time ``robocop-mission check missions/pickup.mission`` from the shell.

Each run is a fresh interpreter, so the figure includes Python's start, the imports,
building the parser, loading the world and checking. The runs of ``check`` alternate
with runs of ``python -c pass`` (the interpreter's own start, the floor), of a
process that only imports the libraries a check needs (:data:`LIBRARIES`: the floor
under the project's own code) and, with ``--run-start``, of ``robocop-mission run
--help``. Prints the median and best wall
times [s], the median CPU time (user + system) of the child, which a busy machine
disturbs less, and each median's ratio to ``python -c pass``'s. Then, from ``--runs``
more fresh interpreters, where a check's time goes: importing the command, building
the parser, loading the world, parsing and checking (medians of CPU time [ms]).

The caches (parser tables, collision facts) are warm: the first run fills them and is
not counted. So is the bytecode: the children write and read their ``.pyc`` files, as
a shell does, whatever ``PYTHONDONTWRITEBYTECODE`` says here; they keep them in a
folder of the bench's own (``PYTHONPYCACHEPREFIX``), never beside the sources. A second
line of ``check`` runs without the project's ``.pyc`` (every one of its modules compiled
at each start, the libraries' read from theirs): what a check costs where bytecode is
never written.

    python bench/check_time.py [--runs 10] [--run-start] [MISSION]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
# What the ``robocop-mission`` script that pip installs runs.
SCRIPT = ("import sys\n"
          "from robocop_dsl.cli.main import entry_point\n"
          "sys.argv[0] = 'robocop-mission'\n"
          "sys.exit(entry_point())\n")
LIBRARIES = "import lark, networkx, numpy, yaml"
"""What ``check`` cannot do without: lark parses the mission, PyYAML reads the world,
numpy holds its joint limits and poses, networkx the state graph."""
# One check, phase by phase, in CPU seconds, printed as JSON.
PHASES = """
import json, sys, time
from pathlib import Path
clock = time.process_time
marks = [clock()]
from robocop_dsl.cli.main import build_parser
from robocop_dsl.compile import WorldCache, build_state_graph, check_file
from robocop_dsl.compile.load import _world_of
from robocop_dsl.check import check_graph, check_mission
from robocop_dsl.lang import mission_grammar, parse_file
marks.append(clock())
mission_grammar()
marks.append(clock())
parsed = parse_file(sys.argv[1])
marks.append(clock())
_, world, _ = _world_of(parsed.mission, parsed.source, WorldCache())
marks.append(clock())
ctx = check_mission(parsed.mission, parsed.source, world, Path(sys.argv[1]).parent.resolve())
check_graph(ctx, ctx.expanded, build_state_graph(ctx.expanded))
marks.append(clock())
names = ("imports", "parser tables", "parse", "world", "check")
print(json.dumps(dict(zip(names, (b - a for a, b in zip(marks, marks[1:]))))))
"""


def _child_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def bytecode_environments(folder: Path) -> tuple[dict, dict]:
    """The children's environments: with bytecode written and read under ``folder``/all,
    and with the project's left out (``folder``/others holds every ``.pyc`` but the
    project's and none is written). Call :func:`without_project` once ``folder``/all is
    filled."""
    with_pyc = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    with_pyc["PYTHONPYCACHEPREFIX"] = str(folder / "all")
    without = dict(with_pyc, PYTHONDONTWRITEBYTECODE="1",
                   PYTHONPYCACHEPREFIX=str(folder / "others"))
    return with_pyc, without


def without_project(folder: Path) -> None:
    """Copy the ``.pyc`` files of ``folder``/all to ``folder``/others, the project's
    left out."""
    shutil.copytree(folder / "all", folder / "others")
    shutil.rmtree(folder / "others" / REPO.relative_to(REPO.anchor), ignore_errors=True)


def timed(arguments: list, env: dict) -> tuple[float, float, subprocess.CompletedProcess]:
    """Wall-clock and CPU seconds of ``python ARGUMENTS`` in a new process."""
    cpu, start = _child_cpu(), time.perf_counter()
    done = subprocess.run([sys.executable, *arguments], cwd=REPO, capture_output=True,
                          text=True, env=env)
    return time.perf_counter() - start, _child_cpu() - cpu, done


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mission", nargs="?", default=REPO / "missions" / "pickup.mission",
                        type=Path)
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--run-start", action="store_true",
                        help="also time `robocop-mission run --help`")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="check-time-") as folder:
        measure(args, Path(folder))


def measure(args, folder: Path) -> None:
    """Print the tables, the children's bytecode kept under ``folder``."""
    with_pyc, without = bytecode_environments(folder)
    check = ["-c", SCRIPT, "check", str(args.mission)]
    lines = [("python -c pass", ["-c", "pass"], with_pyc),
             ("import its libraries only", ["-c", LIBRARIES], with_pyc),
             (f"check {args.mission.name}", check, with_pyc),
             ("check, no project .pyc", check, without)]
    if args.run_start:
        lines.append(("run --help", ["-c", SCRIPT, "run", "--help"], with_pyc))
    for arguments in dict.fromkeys(tuple(arguments) for _, arguments, _ in lines):
        _, _, done = timed(list(arguments), with_pyc)
        if done.returncode not in (0, 1):
            sys.exit(f"check failed ({done.returncode}):\n{done.stdout}{done.stderr}")
    without_project(folder)
    print("The children write and read bytecode as a shell does (PYTHONDONTWRITEBYTECODE "
          "unset, a warm-up run first);\n'no project .pyc' compiles the project's "
          "modules at every start.\n")
    times = {label: ([], []) for label, _, _ in lines}
    for _ in range(args.runs):
        for label, arguments, env in lines:
            wall, cpu, _ = timed(arguments, env)
            times[label][0].append(wall)
            times[label][1].append(cpu)
    floor = statistics.median(times[lines[0][0]][0])
    print(f"{'command':<28} {'wall median':>11} {'best':>7} {'CPU median':>10} {'ratio':>6}")
    for label, (walls, cpus) in times.items():
        median = statistics.median(walls)
        print(f"{label:<28} {median:>11.3f} {min(walls):>7.3f} "
              f"{statistics.median(cpus):>10.3f} {median / floor:>6.2f}")
    phases: dict[str, list] = {}
    for _ in range(args.runs):
        done = subprocess.run([sys.executable, "-c", PHASES, str(args.mission)], cwd=REPO,
                              capture_output=True, text=True, check=True, env=with_pyc)
        for name, seconds in json.loads(done.stdout).items():
            phases.setdefault(name, []).append(seconds)
    print(f"\n{'where a check goes (CPU)':<28} {'median ms':>11}")
    for name, seconds in phases.items():
        print(f"{name:<28} {statistics.median(seconds) * 1e3:>11.1f}")


if __name__ == "__main__":
    main()
