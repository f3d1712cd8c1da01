"""Run the checker fuzzer (tests/test_fuzz_checker.py) on 10,000 inputs, in batches.

Each batch runs the three fuzz tests (missions from the grammar, real missions
mutated, real worlds mutated) with ``ROBOCOP_FUZZ_EXAMPLES`` inputs each and its own
Hypothesis seed, in a fresh pytest process. Prints per batch the inputs run (counted
from Hypothesis' statistics), failures (a traceback or a diagnostic out of place) and
the time; then the totals.

    python bench/fuzz_checker.py [--inputs 10000] [--batch 1000] [--seed 1]
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
TESTS = 3


def batch(examples: int, seed: int) -> tuple[int, int, float, str]:
    """Inputs run, failed tests, seconds and pytest's output of one batch."""
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
         str(REPO / "tests" / "test_fuzz_checker.py"), f"--hypothesis-seed={seed}",
         "--hypothesis-show-statistics"],
        env={**os.environ, "ROBOCOP_FUZZ_EXAMPLES": str(examples)}, cwd=REPO,
        capture_output=True, text=True)
    seconds = time.perf_counter() - start
    inputs = sum(int(n) + int(f) for n, f in re.findall(
        r"(\d+) passing examples?, (\d+) failing examples?", done.stdout))
    failed = int(m.group(1)) if (m := re.search(r"(\d+) failed", done.stdout)) else 0
    if done.returncode not in (0, 1):
        failed = max(failed, 1)
    return inputs, failed, seconds, done.stdout


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--inputs", type=int, default=10_000)
    parser.add_argument("--batch", type=int, default=1_000, help="inputs per batch")
    parser.add_argument("--seed", type=int, default=1, help="seed of the first batch")
    args = parser.parse_args()
    per_test = -(-args.batch // TESTS)
    total_inputs = total_failed = 0
    total_seconds = 0.0
    print(f"{'batch':>5} {'seed':>6} {'inputs':>7} {'failed':>6} {'s':>7} {'ms/input':>8}")
    number = 0
    while total_inputs < args.inputs:
        number += 1
        inputs, failed, seconds, output = batch(per_test, args.seed + number - 1)
        total_inputs, total_failed = total_inputs + inputs, total_failed + failed
        total_seconds += seconds
        print(f"{number:>5} {args.seed + number - 1:>6} {inputs:>7} {failed:>6} "
              f"{seconds:>7.0f} {seconds * 1e3 / max(inputs, 1):>8.1f}", flush=True)
        if failed or not inputs:
            print(output[-4000:])
            break
    print(f"{'all':>5} {'':>6} {total_inputs:>7} {total_failed:>6} {total_seconds:>7.0f} "
          f"{total_seconds * 1e3 / max(total_inputs, 1):>8.1f}")
    return 1 if total_failed or total_inputs < args.inputs else 0


if __name__ == "__main__":
    sys.exit(main())
