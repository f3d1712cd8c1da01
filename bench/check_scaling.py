"""How ``check`` time grows with a mission's size: a chain of N states, and N states
each with N clauses, checked against the Panda world in this process.

Prints, per size, the text's length, the CPU time of parsing + checking + compiling
(best of ``--runs``), the CPU time per kB and its ratio to the smallest size's (a
ratio near 1 at every size is linear growth), and the process's peak RSS so far (sizes
grow, so it is the peak of the largest checked yet). The world is loaded once before
timing.

    python bench/check_scaling.py [--runs 2] [--chain 1000,2000,4000,10000]
                                  [--clauses 50,100,200,300]

(``--chain ""`` or ``--clauses ""`` leaves a table out, for its own peak RSS.)
"""

from __future__ import annotations

import argparse
import resource
import time

from robocop_dsl.compile import WorldCache, check_source
from robocop_dsl.resources import ROBOTS_DIR

WORLD = ROBOTS_DIR / "panda" / "panda_on_table.yaml"


def chain(states: int) -> str:
    """``states`` states in a row, each left after 1 s, the last to ``done``."""
    lines = ['mission chain "states in a row"', f'world "{WORLD}"', "start s0"]
    for i in range(states):
        after = f"s{i + 1}" if i + 1 < states else "done"
        lines.append(f"state s{i} {{\n    when elapsed > 1 s -> {after}\n}}")
    return "\n".join(lines + ["final done"]) + "\n"


def clauses(states: int) -> str:
    """``states`` states, each with ``states`` clauses to other states and ``done``."""
    lines = ['mission mesh "states x clauses"', f'world "{WORLD}"', "start s0"]
    for i in range(states):
        body = [f"    when elapsed > {j + 1} s -> s{(i + j + 1) % states}"
                for j in range(states - 1)]
        body.append(f"    when elapsed > {states + 1} s -> done")
        lines.append(f"state s{i} {{\n" + "\n".join(body) + "\n}")
    return "\n".join(lines + ["final done"]) + "\n"


def cpu_seconds(text: str, cache: WorldCache, runs: int) -> float:
    """Best CPU time (s) of checking ``text``; fails loudly if it does not check."""
    best = float("inf")
    for _ in range(runs):
        start = time.process_time()
        result = check_source(text, "scaling.mission", cache=cache)
        best = min(best, time.process_time() - start)
        assert result.mission is not None, [d.headline() for d in result.diagnostics[:3]]
    return best


def table(name: str, sizes: list[int], make, cache: WorldCache, runs: int) -> None:
    print(f"\n{name}")
    print(f"{'size':>8} {'kB':>8} {'CPU s':>8} {'ms/kB':>8} {'ratio':>6} {'peak MB':>8}")
    first = None
    for size in sizes:
        text = make(size)
        seconds = cpu_seconds(text, cache, runs)
        per_kb = seconds * 1e3 / (len(text) / 1e3)
        first = first or per_kb
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        print(f"{size:>8} {len(text) / 1e3:>8.0f} {seconds:>8.2f} {per_kb:>8.2f} "
              f"{per_kb / first:>6.2f} {peak:>8.0f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=2)
    parser.add_argument("--chain", default="1000,2000,4000,10000")
    parser.add_argument("--clauses", default="50,100,200,300")
    args = parser.parse_args()
    cache = WorldCache()
    cpu_seconds(chain(3), cache, 1)
    for name, sizes, make in (("states in a row", args.chain, chain),
                              ("N states x N clauses", args.clauses, clauses)):
        if sizes:
            table(name, [int(n) for n in sizes.split(",")], make, cache, args.runs)


if __name__ == "__main__":
    main()
