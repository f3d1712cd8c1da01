"""Drive a mission from a hand-written periodic loop instead of ``runner.run()``.

The loop owns the timing, as a robot's own control thread would: it calls
``runner.step()`` once per control period (sleeping to each period's deadline with
``--realtime``), raises the mission's ``go`` event from Python when the operator would
press a button (``--go-at``), and ends with ``runner.finish()``, which returns the
result. ``step()`` keeps returning ``True`` while the robot is brought to rest after
the outcome is decided, so the loop also times the stop.

Usage: ``python examples/user_loop.py [--realtime] [--go-at 1.0]``
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from robocop_dsl.runtime import load_mission

MISSION = Path(__file__).resolve().parent / "operator_go.mission"


def main(argv: list | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--realtime", action="store_true",
                        help="keep to the control period (default: as fast as possible)")
    parser.add_argument("--go-at", type=float, default=1.0, metavar="SECONDS",
                        help="mission time at which the operator says go (default 1 s)")
    args = parser.parse_args(argv)

    runner = load_mission(MISSION).runner()
    runner.start()
    print(f"start in {runner.state} (period {runner.time_step * 1e3:g} ms)")
    deadline = time.perf_counter()
    raised = False
    while runner.step():
        if not raised and runner.time >= args.go_at:
            runner.emit("go")
            raised = True
            print(f"{runner.time:7.3f} s  go raised in {runner.state}")
        if args.realtime:
            deadline += runner.time_step
            time.sleep(max(deadline - time.perf_counter(), 0.0))
    result = runner.finish()
    for transition in result.transitions:
        print(f"{transition.time:7.3f} s  {transition.source} -> {transition.target}")
    print(f"outcome: {result.outcome}  final state: {result.final_state}  "
          f"mission time: {result.mission_time:.3f} s  cycles: {result.cycles}")
    return 0 if result.outcome == "success" else 1


if __name__ == "__main__":
    sys.exit(main())
