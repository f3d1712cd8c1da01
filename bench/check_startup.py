"""What the parser cache is worth: building the mission parser, and a whole ``check``.

Parser: built in this process with lark's shared temporary-folder cache (``cache=True``,
which this package no longer uses: lark unpickles that file before checking it), with
the private cache file :func:`robocop_dsl.lang.parser.private_cache` picks, and with
no cache. Check: ``python -m robocop_dsl check MISSION`` in fresh interpreters, with
the private cache warm and with no cache (a cache folder others may write to is
refused). Prints best-of-``--runs`` times and ratios to the first row of each table.

    python bench/check_startup.py [--runs 5] [MISSION]
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from lark import Lark

from robocop_dsl.lang.parser import StatementBreaks, private_cache
from robocop_dsl.resources import GRAMMAR_DIR

REPO = Path(__file__).resolve().parent.parent


def build_seconds(cache, runs: int) -> float:
    """Best wall time (s) of building the parser with lark's ``cache`` option (the
    first build fills a cache; it is not counted)."""
    text = (GRAMMAR_DIR / "mission.lark").read_text(encoding="utf-8")
    times = []
    for _ in range(runs + 1):
        start = time.perf_counter()
        Lark(text, parser="lalr", lexer="contextual", propagate_positions=True,
             postlex=StatementBreaks(), import_paths=[GRAMMAR_DIR], cache=cache)
        times.append(time.perf_counter() - start)
    return min(times[1:])


def check_seconds(mission: Path, cache_home: str, runs: int) -> tuple[float, float]:
    """Best wall time and best child CPU time (s) of ``check`` in a new interpreter."""
    env = {**os.environ, "XDG_CACHE_HOME": cache_home}
    walls, cpus = [], []
    for _ in range(runs + 1):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "robocop_dsl", "check", str(mission)],
                              env=env, capture_output=True, text=True)
        walls.append(time.perf_counter() - start)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
        assert done.returncode == 0, done.stdout + done.stderr
    return min(walls[1:]), min(cpus[1:])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mission", nargs="?", default=str(REPO / "missions/pickup.mission"))
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    grammar = (GRAMMAR_DIR / "mission.lark").read_text(encoding="utf-8")
    with tempfile.TemporaryDirectory() as home:
        os.environ["XDG_CACHE_HOME"] = home
        rows = [("shared temporary folder (cache=True)", build_seconds(True, args.runs)),
                ("private cache folder", build_seconds(private_cache(grammar), args.runs)),
                ("no cache", build_seconds(False, args.runs))]
    print(f"{'building the parser':<40} {'ms':>8} {'ratio':>6}")
    for name, seconds in rows:
        print(f"{name:<40} {seconds * 1e3:>8.1f} {seconds / rows[0][1]:>6.2f}")
    with tempfile.TemporaryDirectory() as private, tempfile.TemporaryDirectory() as shared:
        os.mkdir(Path(shared) / "robocop-mission", 0o777)
        os.chmod(Path(shared) / "robocop-mission", 0o777)
        rows = [("private cache, warm", *check_seconds(Path(args.mission), private, args.runs)),
                ("no cache", *check_seconds(Path(args.mission), shared, args.runs))]
    print(f"\n{'check ' + Path(args.mission).name:<40} {'wall s':>8} {'CPU s':>8} {'ratio':>6}")
    for name, wall, cpu in rows:
        print(f"{name:<40} {wall:>8.2f} {cpu:>8.2f} {cpu / rows[0][2]:>6.2f}")


if __name__ == "__main__":
    main()
