"""Control-loop cycle times with and without the viewer.

Runs the pickup mission headless (with an observer that ignores the records, as the
command line's progress display does), with the live Meshcat viewer (its own server on
127.0.0.1, publishing every 40 ms from its thread) and with the replay recorder, several
times each, interleaved in rotating order. Prints the median and 99th percentile of
the runner's cycle times (``RunResult.cycle_times``: read, state machine, QP, write),
each taken per run and then the median over the runs (robust to a run disturbed by
other work on the machine), with their ratio to the headless run. Run it on an
otherwise idle machine. As fast as the machine goes by default; the live viewer is
meant for ``--realtime`` runs, where the loop sleeps between cycles.

Usage: ``python bench/viewer_overhead.py [--realtime] [--repeats N] [--mission FILE]``
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np

from robocop_dsl.runtime import Observer, load_mission
from robocop_dsl.viewer import LiveViewer, ReplayRecorder, viewer_options

MISSION = Path(__file__).resolve().parent.parent / "missions" / "pickup.mission"


class _Ignore(Observer):
    """Takes each cycle's record and does nothing with it."""


def headless(world, folder):
    # an observer, as in ``robocop-mission run`` (its progress display is one), so that
    # every mode pays the same for the records the runner makes
    return [_Ignore()]


def live(world, folder):
    return [LiveViewer(world, options=viewer_options(world))]


def recorded(world, folder):
    return [ReplayRecorder(world, Path(folder) / "replay.html", viewer_options(world))]


MODES = {"headless": headless, "viewer": live, "record": recorded}


def run_once(mission_path: Path, make_observers, realtime: bool) -> np.ndarray:
    """Cycle times [s] of one run with the observers ``make_observers`` gives."""
    mission = load_mission(mission_path)
    runner = mission.runner()
    with tempfile.TemporaryDirectory() as folder:
        observers = make_observers(mission.world, folder)
        for observer in observers:
            runner.add_observer(observer)
        result = runner.run(realtime=realtime)
        for observer in observers:
            if isinstance(observer, LiveViewer):
                observer.close()
                if observer.problems:
                    raise SystemExit(f"viewer failed: {observer.problems[0]}")
    if result.outcome != "success":
        raise SystemExit(f"run ended with {result.outcome}: {result.message}")
    return result.cycle_times


def main(argv: list | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--realtime", action="store_true", help="sleep to the control period")
    parser.add_argument("--repeats", type=int, default=3, help="runs per mode (default 3)")
    parser.add_argument("--mission", type=Path, default=MISSION)
    args = parser.parse_args(argv)
    runs = {mode: [] for mode in MODES}
    names = list(MODES)
    for repeat in range(args.repeats):
        shift = repeat % len(names)          # each mode in each place of the round in turn
        for mode in names[shift:] + names[:shift]:
            cycle_times = run_once(args.mission, MODES[mode], args.realtime) * 1e3
            runs[mode].append((np.median(cycle_times), np.percentile(cycle_times, 99)))
    summary = {mode: np.median(np.array(values), axis=0) for mode, values in runs.items()}
    base_median, base_p99 = summary["headless"]
    print(f"{args.mission.name}, {'real time' if args.realtime else 'as fast as possible'}, "
          f"{args.repeats} interleaved runs per mode; median over the runs of each run's "
          "cycle-time median and p99")
    print(f"{'mode':<10}{'median ms':>11}{'p99 ms':>9}{'median/headless':>17}"
          f"{'p99/headless':>14}")
    for mode, (median, p99) in summary.items():
        print(f"{mode:<10}{median:>11.3f}{p99:>9.3f}{median / base_median:>17.2f}"
              f"{p99 / base_p99:>14.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
