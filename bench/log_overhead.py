"""What writing a run costs its control loop: ``--log`` (events, Parquet, ``run.mcap``)
and ``--foxglove`` (the live server), against the same run without them.

Every run is ``robocop-mission run`` in a fresh process, as a user starts it (imports
included: they used to land in the loop), the modes taken in turn, round after round,
so that other work on the machine weighs on all of them alike. In the ``--foxglove``
modes a client in a process of its own (as Foxglove on the same machine) connects,
naming the protocol ``foxglove.websocket.v1``, and subscribes to every topic. Two tables:

- real time (``--realtime``): per mode, the overruns of each run (cycles that started
  more than a period late), the median over the runs of each run's cycle-time p99 and
  max [ms] and, with ``--foxglove``, of the messages the client received; then, per
  run, the time the hypervisor stole from the processor the loop ran on (the ``steal``
  column of ``/proc/stat``, sampled every 5 ms with the processor the loop last ran on)
  and the overruns left when those whose stall overlaps a stolen sample are taken out
  (on a virtual machine, the stalls the run itself causes are among those), how many
  times the loop's thread was taken off its processor while it could run, and how long
  it waited, ready to run, for a processor that other threads or processes of the
  machine held (its run-queue delay);
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
import os
import socket
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent


def child(argv: list) -> None:
    """In the child process: run the command line, print what the runs measured."""
    from robocop_dsl.cli.main import main
    from robocop_dsl.runtime.records import Observer
    from robocop_dsl.runtime.runner import Runner

    timed: dict = {}
    late: list = []
    run, start = Runner.run, Runner.start

    class Overruns(Observer):
        """Keeps each overrun's time (the monotonic clock, as the sampler's) and delay
        [s]."""

        wants_tasks = False

        def on_event(self, event):
            if event.kind == "overrun":
                late.append((time.monotonic(), event.data["late"]))

    def timed_start(self):
        self.add_observer(Overruns())
        timed["period"] = self.time_step
        start(self)
        timed.setdefault("start", time.perf_counter())
        timed.setdefault("cpu", time.thread_time())
        timed.setdefault("waited", waited_for_processor())
        timed.setdefault("preempted", preemptions())

    def timed_run(self, *args, **kwargs):
        result = run(self, *args, **kwargs)
        timed.update(wall=time.perf_counter() - timed["start"],
                     cpu=time.thread_time() - timed["cpu"], result=result,
                     waited=waited_for_processor() - timed["waited"],
                     preempted=preemptions() - timed["preempted"])
        return result

    Runner.start, Runner.run = timed_start, timed_run
    with contextlib.redirect_stdout(io.StringIO()):
        code = main(["run"] + argv)
    result = timed["result"]
    times = np.asarray(result.cycle_times) * 1e3
    print(json.dumps({"code": code, "outcome": result.outcome, "overruns": result.overruns,
                      "p99": float(np.percentile(times, 99)), "max": float(times.max()),
                      "late": late, "period": timed["period"], "waited": timed["waited"],
                      "preempted": timed["preempted"],
                      "speed-up": result.mission_time / timed["wall"],
                      "loop speed-up": result.mission_time / timed["cpu"]}))


def waited_for_processor() -> float:
    """How long [s] the calling thread has waited, ready to run, for a processor (its
    run-queue delay: the processor held by other threads or processes of this machine,
    not by the hypervisor); 0 where ``/proc/thread-self/schedstat`` is missing."""
    try:
        return int(Path("/proc/thread-self/schedstat").read_text().split()[1]) * 1e-9
    except (OSError, IndexError, ValueError):
        return 0.0


def preemptions() -> int:
    """How many times the calling thread was taken off its processor while it could run
    (Linux's ``nonvoluntary_ctxt_switches``: a thread that woke up, or the end of its
    time slice); 0 where ``/proc/thread-self/status`` is missing."""
    try:
        status = Path("/proc/thread-self/status").read_text()
        return int(status.split("nonvoluntary_ctxt_switches:")[1].split()[0])
    except (OSError, IndexError, ValueError):
        return 0


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


STEAL_SAMPLE = 0.005
"""[s] Between two samples of the stolen time."""


def stolen() -> dict:
    """Per processor, the time [s] the hypervisor has stolen from it (``/proc/stat``);
    empty where that is not known."""
    try:
        lines = Path("/proc/stat").read_text().splitlines()
    except OSError:
        return {}
    tick = os.sysconf("SC_CLK_TCK")
    return {int(fields[0][3:]): int(fields[8]) / tick for fields in map(str.split, lines)
            if fields and fields[0][3:].isdigit() and len(fields) > 8}


def processor(pid: int) -> int | None:
    """The processor the process's main thread last ran on."""
    try:
        return int(Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[36])
    except (OSError, ValueError, IndexError):
        return None


def sample_steal(process: subprocess.Popen) -> tuple:
    """Until ``process`` ends: ``(time, stolen from the loop's processor since the last
    sample [s])`` every :data:`STEAL_SAMPLE`, by a thread of this process; returns the
    samples and the thread."""
    samples: list = []

    def sample():
        before = stolen()
        while process.poll() is None:
            time.sleep(STEAL_SAMPLE)
            now, on = stolen(), processor(process.pid)
            samples.append((time.monotonic(), now.get(on, 0.0) - before.get(on, 0.0)))
            before = now

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    return samples, sampler


def clear_of_steal(late: list, samples: list, period: float) -> int:
    """How many overruns (``(time, delay)``, noticed at ``time`` [s]) stalled while no time
    was stolen from the loop's processor: the stall runs from a period before the
    late cycle was due to when it was noticed, widened by a sample each side."""
    stolen_at = [at for at, taken in samples if taken > 0]
    return sum(not any(noticed - delay - period - STEAL_SAMPLE <= at
                       <= noticed + 2 * STEAL_SAMPLE for at in stolen_at)
               for noticed, delay in late)


def measure(mission: str, flags: list) -> dict:
    port = str(free_port())
    client = (subprocess.Popen([sys.executable, __file__, "--client", port],
                               stdout=subprocess.PIPE, text=True)
              if "--foxglove" in flags else None)
    with tempfile.TemporaryDirectory() as folder:
        flags = [flag.replace("LOG", folder).replace("PORT", port) for flag in flags]
        child_process = subprocess.Popen([sys.executable, __file__, "--child", mission,
                                          *flags], cwd=REPO, stdout=subprocess.PIPE,
                                         stderr=subprocess.PIPE, text=True)
        samples, sampler = sample_steal(child_process)
        out, err = child_process.communicate()
        sampler.join()
    lines = [line for line in out.splitlines() if line.startswith("{")]
    if not lines:
        if client is not None:
            client.kill()
        raise SystemExit(f"run {flags} failed:\n{err[-2000:]}")
    result = json.loads(lines[-1])
    result["stolen"] = sum(taken for _, taken in samples)
    result["clear"] = clear_of_steal(result["late"], samples, result["period"])
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
    print("\nthe same runs: time stolen from the loop's processor [ms], times the loop was "
          "taken off its processor while it could run, time it waited for a processor "
          "held by others [ms], and the overruns whose stall overlaps no stolen sample "
          "(each run, then their sum)")
    print(f"{'mode':<18}{'stolen ms':<26}{'preempted':<32}{'waited ms':<26}"
          f"{'clear of steal':<20}{'sum':>5}")
    for mode, results in runs.items():
        columns = [" ".join(f"{result[key] * scale:.0f}" for result in results)
                   for key, scale in (("stolen", 1e3), ("preempted", 1), ("waited", 1e3))]
        clear = [result["clear"] for result in results]
        print(f"{mode:<18}{columns[0]:<26}{columns[1]:<32}{columns[2]:<26}"
              f"{' '.join(map(str, clear)):<20}{sum(clear):>5}")


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
