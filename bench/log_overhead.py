"""What writing a run costs its control loop: ``--log`` (events, Parquet, ``run.mcap``)
and ``--foxglove`` (the live server), against the same run without them.

Every run is ``robocop-mission run`` in a fresh process, as a user starts it (imports
included: they used to land in the loop), the modes taken in turn, round after round,
so that other work on the machine weighs on all of them alike. In the ``--foxglove``
modes a client in a process of its own (as Foxglove on the same machine) connects,
naming the protocol ``foxglove.websocket.v1``, and subscribes to every topic. Two tables:

- real time (``--realtime``): per mode, the overruns of each run (cycles that started
  more than a period late), the median over the runs of each run's cycle-time p99 and
  max [ms] and, with ``--foxglove``, of the messages the client received;
- headless: per mode, each run's speed-up (mission time / wall time from the first
  cycle to the end of the run, the log's closing included, its setup before the first
  cycle not) and their median, and the median's ratio to the run without a log; then
  the same on the loop thread's CPU time (what the log costs the loop itself, whatever
  else the machine runs: the writing process works on another core when there is one).

Usage: python bench/log_overhead.py [--rounds 3] [--mission missions/pickup.mission]
       [--skip-realtime] [--skip-headless]
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import io
import json
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent


def child(argv: list) -> None:
    """In the child process: run the command line, print what the runs measured."""
    from robocop_dsl.cli.main import main
    from robocop_dsl.runtime.runner import Runner

    timed: dict = {}
    run, start = Runner.run, Runner.start

    def timed_start(self):
        start(self)
        timed.setdefault("start", time.perf_counter())
        timed.setdefault("cpu", time.thread_time())

    def timed_run(self, *args, **kwargs):
        result = run(self, *args, **kwargs)
        timed.update(wall=time.perf_counter() - timed["start"],
                     cpu=time.thread_time() - timed["cpu"], result=result)
        return result

    Runner.start, Runner.run = timed_start, timed_run
    with contextlib.redirect_stdout(io.StringIO()):
        code = main(["run"] + argv)
    result = timed["result"]
    times = np.asarray(result.cycle_times) * 1e3
    print(json.dumps({"code": code, "outcome": result.outcome, "overruns": result.overruns,
                      "p99": float(np.percentile(times, 99)), "max": float(times.max()),
                      "speed-up": result.mission_time / timed["wall"],
                      "loop speed-up": result.mission_time / timed["cpu"]}))


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def watch(port: str) -> None:
    """In the client's process: connect to the run's Foxglove server as soon as it
    listens, subscribe to every channel, print how many messages came until it closed."""
    import websockets

    async def received() -> int:
        while True:
            try:
                connection = await websockets.connect(
                    f"ws://127.0.0.1:{port}", subprotocols=["foxglove.websocket.v1"],
                    compression=None, max_size=None)
                break
            except OSError:
                await asyncio.sleep(0.05)
        count = 0
        async with connection as ws:
            with contextlib.suppress(websockets.ConnectionClosed):
                async for message in ws:
                    if isinstance(message, bytes):
                        count += 1
                    elif json.loads(message)["op"] == "advertise":
                        await ws.send(json.dumps({"op": "subscribe", "subscriptions": [
                            {"id": c["id"], "channelId": c["id"]}
                            for c in json.loads(message)["channels"]]}))
        return count

    print(asyncio.run(received()))


def measure(mission: str, flags: list) -> dict:
    port = str(free_port())
    client = (subprocess.Popen([sys.executable, __file__, "--client", port],
                               stdout=subprocess.PIPE, text=True)
              if "--foxglove" in flags else None)
    with tempfile.TemporaryDirectory() as folder:
        flags = [flag.replace("LOG", folder).replace("PORT", port) for flag in flags]
        done = subprocess.run([sys.executable, __file__, "--child", mission, *flags],
                              cwd=REPO, capture_output=True, text=True)
    lines = [line for line in done.stdout.splitlines() if line.startswith("{")]
    if not lines:
        if client is not None:
            client.kill()
        raise SystemExit(f"run {flags} failed:\n{done.stderr[-2000:]}")
    result = json.loads(lines[-1])
    if client is not None:
        result["received"] = int(client.communicate()[0])
    return result


def interleaved(mission: str, modes: dict, rounds: int) -> dict:
    runs = {mode: [] for mode in modes}
    names = list(modes)
    for round_ in range(rounds):
        shift = round_ % len(names)             # each mode in each place of a round in turn
        for mode in names[shift:] + names[:shift]:
            runs[mode].append(measure(mission, modes[mode]))
    return runs


def realtime_table(mission: str, rounds: int) -> None:
    modes = {"no log": ["--realtime"], "--log": ["--realtime", "--log", "LOG"],
             "--foxglove": ["--realtime", "--foxglove", "127.0.0.1:PORT"],
             "--log --foxglove": ["--realtime", "--log", "LOG", "--foxglove",
                                  "127.0.0.1:PORT"]}
    runs = interleaved(mission, modes, rounds)
    print(f"\n{Path(mission).name}, --realtime, {rounds} rounds: overruns of each run, "
          "median over the runs of the cycle-time p99 and max")
    print(f"{'mode':<18}{'overruns':<22}{'p99 ms':>9}{'max ms':>9}{'received':>10}")
    for mode, results in runs.items():
        overruns = " ".join(str(result["overruns"]) for result in results)
        received = (f"{np.median([r['received'] for r in results]):>10.0f}"
                    if "received" in results[0] else "")
        print(f"{mode:<18}{overruns:<22}{np.median([r['p99'] for r in results]):>9.3f}"
              f"{np.median([r['max'] for r in results]):>9.3f}{received}")


def headless_table(mission: str, rounds: int) -> None:
    modes = {"no log": [], "--log": ["--log", "LOG"]}
    runs = interleaved(mission, modes, rounds)
    print(f"\n{Path(mission).name}, headless, {rounds} rounds: speed-up of each run "
          "(mission time / wall time, then / the loop thread's CPU time)")
    for key in ("speed-up", "loop speed-up"):
        base = np.median([result[key] for result in runs["no log"]])
        print(f"{'mode':<18}{key + 's':<40}{'median':>8}{'/ no log':>10}")
        for mode, results in runs.items():
            speeds = [result[key] for result in results]
            print(f"{mode:<18}{' '.join(f'{s:.1f}x' for s in speeds):<40}"
                  f"{np.median(speeds):>7.1f}x{np.median(speeds) / base:>10.2f}")


def main() -> None:
    if sys.argv[1:2] == ["--child"]:
        child(sys.argv[2:])
        return
    if sys.argv[1:2] == ["--client"]:
        watch(sys.argv[2])
        return
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--mission", default="missions/pickup.mission")
    parser.add_argument("--skip-realtime", action="store_true")
    parser.add_argument("--skip-headless", action="store_true")
    args = parser.parse_args()
    if not args.skip_headless:
        headless_table(args.mission, args.rounds)
    if not args.skip_realtime:
        realtime_table(args.mission, args.rounds)


if __name__ == "__main__":
    main()
