"""``robocop-mission run FILE``: run a mission headless (default) or in real time,
optionally shown in Meshcat (``--viewer``), recorded as an HTML replay (``--record``),
logged (``--log DIR``: events, time series and ``run.mcap``) and served live to
Foxglove (``--foxglove [HOST:PORT]``).

Exit codes: 0 success outcome, 1 failure outcome (or ``--duration`` reached first),
2 invalid mission (or viewer or Foxglove options), 3 run-time fault (or no Meshcat
server, or a Foxglove address that cannot be served), 130 interrupted (SIGINT,
Ctrl-C), 143 terminated (SIGTERM). A signal, even during
start-up, ends the run the way a final state does: the robot decelerates and holds,
the log is complete; a second signal changes nothing.
"""

from __future__ import annotations

import argparse
import gc
import math
import signal
import sys
import threading

from ..diagnostics import DiagnosticError, render_all
from .events import scheduled_event
from .stop_signals import StopSignals

DEFAULT_ADDRESS = "127.0.0.1:8765"     # of --foxglove

EXIT_CODES = {"success": 0, "failure": 1, "stopped": 1, "fault": 3, "interrupted": 130}
VIEWER_SYNC = 5.0   # [s] at most to show the last cycle before waiting or exiting


def _duration(text: str) -> float:
    """A ``--duration``: a finite number of seconds above zero."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number of seconds") from None
    if not math.isfinite(value) or value <= 0:
        raise argparse.ArgumentTypeError(f"{text}: a duration is a finite number of "
                                         "seconds above 0")
    return value


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "run", help="run a mission against the simulated robot",
        description="Check and run a mission. Headless and as fast as the machine goes "
                    "unless --realtime or --viewer; prints progress and a summary.")
    parser.add_argument("file", help="the .mission file")
    parser.add_argument("--realtime", action=argparse.BooleanOptionalAction, default=None,
                        help="sleep to the control period and report overruns "
                             "(default: on with --viewer or --foxglove, off otherwise)")
    parser.add_argument("--viewer", action="store_true",
                        help="show the run in Meshcat: start a server on 127.0.0.1 and "
                             "print the page's URL")
    parser.add_argument("--viewer-url", metavar="ZMQ_URL",
                        help="show the run on the Meshcat server at this ZeroMQ address "
                             "(implies --viewer)")
    parser.add_argument("--no-wait", action="store_true",
                        help="with --viewer, exit when the run ends instead of keeping the "
                             "page served until Ctrl-C")
    parser.add_argument("--record", metavar="FILE",
                        help="write a standalone HTML replay of the run to FILE")
    parser.add_argument("--duration", type=_duration, metavar="SECONDS",
                        help="stop after this much mission time (> 0)")
    parser.add_argument("--solver", help="QP solver (overrides the world's controller)")
    parser.add_argument("--hierarchy", choices=("strict", "weighted"),
                        help="task hierarchy (overrides the world's controller)")
    parser.add_argument("--world", metavar="WORLD.yaml",
                        help="run on this world instead of the one the mission names (a "
                             "variant: the same names, another driver, physics...)")
    parser.add_argument("--log", metavar="DIR",
                        help="write events, time series and run.mcap (ROS 2 messages) to DIR")
    parser.add_argument("--foxglove", nargs="?", const=DEFAULT_ADDRESS, metavar="HOST:PORT",
                        help="serve the run live to Foxglove over its WebSocket protocol "
                             f"(default {DEFAULT_ADDRESS})")
    parser.add_argument("--allow-remote", action="store_true",
                        help="let --foxglove serve an address other than the loopback's")
    parser.add_argument("--campaign", metavar="CAMPAIGN.yaml",
                        help="run one job of this campaign: its world variant, controller "
                             "settings and sampled conditions (with --job)")
    parser.add_argument("--job", type=int, metavar="N",
                        help="the job to run: the 'job' column of the sweep's results table")
    parser.add_argument("--debug", action="store_true",
                        help="print the Python traceback of a run-time fault")
    parser.add_argument("--event", action="append", default=[], metavar="NAME@TIME",
                        type=scheduled_event,
                        help="raise event NAME at mission time TIME (seconds, or with ms "
                             "or s: go@2.5, go@500ms); repeatable")
    parser.set_defaults(command=run)


def run(args) -> int:
    with RunStopSignals() as signals:
        log = None
        if args.log:
            from ..ecosystem.log_process import LogProcess

            try:
                log = LogProcess(args.log)      # starts at once: its imports overlap ours
            except OSError as error:
                print(f"robocop-mission run: error: cannot write the log in {args.log}: "
                      f"{error.strerror}", file=sys.stderr)
                return 2
        try:
            return _run(args, signals, log)
        finally:
            if log is not None:
                log.close()


def _run(args, signals, log) -> int:
    from ..runtime.summary import SummaryWatch
    from .event_schedule import EventSchedule
    from .events import unknown_events
    from .progress import ProgressDisplay, print_summary

    if (args.campaign is None) != (args.job is None):
        print("robocop-mission run: error: --campaign and --job go together", file=sys.stderr)
        return 2
    if args.campaign is not None and args.world is not None:
        print("robocop-mission run: error: a campaign job runs on its own world variant; "
              "--world goes without --campaign", file=sys.stderr)
        return 2
    watched = bool(args.viewer or args.viewer_url)
    if args.realtime is None:
        args.realtime = watched or args.foxglove is not None
    address = None
    if args.foxglove is not None:
        from ..ecosystem import FoxgloveAddressError, parse_address

        try:
            address = parse_address(args.foxglove, args.allow_remote)
        except FoxgloveAddressError as error:
            print(f"robocop-mission run: error: {error}", file=sys.stderr)
            return 2
    try:
        mission, runner, duration = _prepare(args)
    except DiagnosticError as error:
        print(render_all(error.diagnostics), file=sys.stderr)
        return 2
    unknown = unknown_events(args.event, mission.spec.events)
    if unknown:
        print("\n".join(f"robocop-mission run: error: {m}" for m in unknown), file=sys.stderr)
        return 2
    if args.event:
        runner.add_observer(EventSchedule(args.event))
    watch = SummaryWatch(mission.spec)
    runner.add_observer(watch)
    realtime = bool(args.realtime or runner.driver.realtime)
    viewer = recorder = None
    if watched or args.record:
        from ..viewer import ViewerConnectionError, ViewerError

        try:
            viewer, recorder = _viewers(args, mission.world, watched)
        except ViewerError as error:
            print(f"error: {error}", file=sys.stderr)
            return 3 if isinstance(error, ViewerConnectionError) else 2
    writers = []
    if address is not None:
        from ..ecosystem import FoxgloveError, foxglove_live

        try:
            writers.append(foxglove_live(mission.world, runner.joint_names, *address,
                                         name=f"robocop-mission: {mission.name}"))
        except FoxgloveError as error:
            print(f"robocop-mission run: error: {error}", file=sys.stderr)
            if viewer is not None:
                viewer.close()
            return 3
        print(f"foxglove: {writers[-1].sink.url}", flush=True)
    if log is not None:
        from ..ecosystem.log_process import LogProcessError
        from ..runtime.writer_thread import BATCH, DROP

        try:
            log.prepare(runner, DROP if realtime else BATCH)
        except LogProcessError as error:
            print(f"robocop-mission run: error: {error}", file=sys.stderr)
            for live in writers:
                live.sink.close()
            if viewer is not None:
                viewer.close()
            return 3
        writers.append(log)
    for observer in writers + [viewer, recorder]:
        if observer is not None:
            runner.add_observer(observer)
    display = ProgressDisplay(mission.name, realtime=realtime)
    runner.add_observer(display)
    signals.attach(runner)
    gc.freeze()     # what was made before the run stays out of the collector's passes
    try:
        result = runner.run(duration=duration, realtime=realtime)
    finally:
        gc.unfreeze()
        display.close()
    print_summary(result, sys.stdout, watch.summary)
    if args.debug and runner.error is not None:
        print(runner.fault_traceback(), file=sys.stderr, end="")
    for writer in writers:
        if writer.dropped:
            print(f"warning: a writer fell behind the loop and dropped {writer.dropped} "
                  "cycles ('dropped' events say which)", file=sys.stderr)
    if args.log:
        print(f"log: {args.log}")
    if recorder is not None:
        for problem in recorder.problems:
            print(f"warning: {problem}", file=sys.stderr)
        if not recorder.problems:
            print(f"replay: {recorder.path}")
    signals.release()
    if viewer is not None:
        _keep_viewer(viewer, wait=not args.no_wait)
    if result.outcome == "interrupted" and signals.received is not None:
        return 128 + signals.received
    return EXIT_CODES[result.outcome]


class RunStopSignals(StopSignals):
    """SIGINT and SIGTERM stop the run instead of raising: one received before the
    runner exists stops it as soon as it is attached."""

    def __init__(self):
        super().__init__()
        self._runner = None

    def attach(self, runner) -> None:
        """Stop ``runner`` on a signal (at once if one came already)."""
        self._runner = runner
        self.stop()

    def stop(self) -> None:
        if self._runner is not None and self.received is not None:
            name = signal.Signals(self.received).name
            self._runner.stop(f"interrupted by {name}")


def _viewers(args, world, watched: bool) -> tuple:
    """The live viewer and the replay recorder the options ask for (``None`` if not),
    made before the run. A viewer that fails during the run says so once, on stderr."""
    from ..viewer import LiveViewer, ReplayRecorder, viewer_options

    options = viewer_options(world)
    viewer = recorder = None
    if watched:
        viewer = LiveViewer(world, zmq_url=args.viewer_url, options=options,
                            on_problem=lambda message: print(f"warning: {message}",
                                                             file=sys.stderr))
        print(f"viewer: {viewer.web_url}")
    if args.record:
        recorder = ReplayRecorder(world, args.record, options)
    return viewer, recorder


def _keep_viewer(viewer, wait: bool) -> None:
    """Show the run's last cycle, then serve the page until Ctrl-C unless ``wait`` is off."""
    viewer.sync(VIEWER_SYNC)
    if wait and not viewer.problems:
        print(f"viewer: {viewer.web_url} (Ctrl-C to quit)")
        try:
            threading.Event().wait()
        except KeyboardInterrupt:
            pass
    viewer.close()


def _prepare(args) -> tuple:
    """The mission, its runner and the mission-time cap [s]: of the file, or of a job of
    ``--campaign`` (its variant, settings and conditions; --solver/--hierarchy override)."""
    from ..runtime import load_mission

    if args.campaign is not None:
        from ..campaign.rerun import campaign_job

        job, prepared = campaign_job(args.campaign, args.job, args.file,
                                     solver=args.solver, hierarchy=args.hierarchy)
        duration = args.duration if args.duration is not None else job.duration
        return prepared.mission, prepared.runner, duration
    world = None
    if args.world is not None:
        from ..world import load_world

        world = load_world(args.world)
    mission = load_mission(args.file, world=world)
    runner = mission.runner(solver=args.solver, hierarchy=args.hierarchy,
                            realtime=args.realtime)
    return mission, runner, args.duration
