"""The writers' threads never hold the loop up: a real-time writer works while the loop
sleeps and drops its oldest batch when it falls behind (a ``dropped`` event says which
cycles); a headless one writes its backlog while the loop waits; cycles packed for the
writing process come back as they were."""

import json
import pickle
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from conftest import MISSIONS
from robocop_dsl.ecosystem.stream import TopicStream
from robocop_dsl.runtime import load_mission
from robocop_dsl.runtime.record_batch import pack, unpack
from robocop_dsl.runtime.records import CycleRecord, Event, Observer
from robocop_dsl.runtime.writer_thread import BATCH, DROP, WAIT, WriterThread


def test_a_real_time_writer_drops_its_oldest_batch():
    started, release, written = threading.Event(), threading.Event(), []

    def work(batch):
        started.set()
        release.wait()
        written.append(batch)

    writer = WriterThread("test", work, 2, DROP)
    writer.put(0)
    started.wait()                              # 0 is being written
    assert [writer.put(batch) for batch in (1, 2, 3, 4)] == [None, None, 1, 2]
    release.set()
    writer.close()
    assert written == [0, 3, 4]


def test_what_a_real_time_writer_keeps_of_a_dropped_batch_goes_on_with_the_next():
    started, release, written = threading.Event(), threading.Event(), []

    def work(batch):
        started.set()
        release.wait()
        written.append(batch)

    def keep(batch):
        return [item for item in batch if isinstance(item, str)]

    writer = WriterThread("test", work, 1, DROP, keep=keep)
    writer.put([0])
    started.wait()
    assert writer.put([1, "enter a"]) is None
    assert writer.put([2, "enter b", 3]) == [1, "enter a"]
    assert writer.put([4]) == ["enter a", 2, "enter b", 3]
    release.set()
    writer.close()
    assert written == [[0], ["enter a", "enter b", 4]]


def test_a_real_time_writer_works_while_the_loop_sleeps():
    """``turn`` returns in the window a cycle opens, not after it."""
    steps = []
    writer = WriterThread("test", lambda batch: (writer.turn(), steps.append(batch)), 4, DROP)
    writer.put(0)
    writer.loop_sleeps(time.perf_counter())     # a late loop: no window
    writer.loop_sleeps(None)                    # a loop that does not sleep: none
    assert not steps
    writer.loop_sleeps(time.perf_counter() + 60.0)
    writer.close()
    assert steps == [0]


def woken(thread_id: int) -> int:
    """How many times a thread of this process has been woken (it gave up its processor
    to wait), as Linux counts them."""
    status = Path(f"/proc/self/task/{thread_id}/status").read_text()
    return int(status.split("voluntary_ctxt_switches:")[1].split()[0])


@pytest.mark.skipif(not Path("/proc/self/task").exists(), reason="Linux's thread counts")
def test_a_real_time_writer_with_nothing_to_write_is_not_woken_by_the_loop():
    """Each cycle, the loop says when it sleeps; a writer with nothing to write must not
    wake for it (each wake-up takes the loop's processor or the interpreter from it)."""
    writer = WriterThread("test", lambda batch: None, 4, DROP)
    thread_id = writer._thread.native_id
    before = woken(thread_id)
    for _ in range(500):
        writer.loop_sleeps(time.perf_counter() + 1e-3)
        time.sleep(1e-3)
    assert woken(thread_id) - before < 50
    writer.close()


def test_a_batch_handed_to_a_real_time_writer_during_a_cycle_waits_for_the_loops_sleep():
    """The loop hands batches over in the middle of a cycle: waking the writer then
    would take the processor from the loop; it is woken when the loop goes to sleep."""
    written = []
    writer = WriterThread("test", written.append, 4, DROP)
    wakes = []
    notify = writer._ready.notify_all
    writer._ready.notify_all = lambda: (wakes.append(len(writer._waiting)), notify())
    writer.loop_sleeps(time.perf_counter() - 1.0)   # a late loop: its cycle goes on
    writer.put(0)
    writer.put(1)
    assert wakes == []
    writer.loop_sleeps(time.perf_counter() + 60.0)
    assert wakes == [2]
    writer.close()
    assert written == [0, 1]


def test_a_headless_writer_writes_its_backlog_while_the_loop_waits():
    written, loop_waited = [], []
    writer = WriterThread("test", written.append, 3, BATCH)
    for batch in range(2):
        writer.put(batch)
    assert written == []                        # the loop goes on, the writer waits
    writer.put(2)                               # full: the loop waits for all of it
    loop_waited.append(list(written))
    writer.put(3)
    writer.close()
    assert loop_waited == [[0, 1, 2]] and written == [0, 1, 2, 3]


def test_what_work_raises_is_raised_by_close():
    def work(batch):
        raise OSError("disk full")

    writer = WriterThread("test", work, 2, WAIT)
    writer.put(0)
    with pytest.raises(OSError, match="disk full"):
        writer.close()


class Blocked:
    """A sink whose first write waits to be released."""

    def __init__(self):
        self.release, self.entered, self.messages = threading.Event(), threading.Event(), []

    def write(self, messages):
        self.entered.set()
        self.release.wait()
        self.messages += messages

    def checkpoint(self):
        pass

    def close(self):
        pass


class Topics:
    """Each cycle as one message, each event as one."""

    def opening(self):
        return []

    def cycles(self, records):
        return [("/cycle", record.cycle, b"") for record in records]

    def event(self, line):
        return [("/event", json.loads(line)["time"], line)]


class Runner:
    """Sleeps a minute after every cycle."""

    time_step = 0.005

    def __init__(self):
        self.reported = []

    @property
    def next_cycle_at(self):
        return time.perf_counter() + 60.0

    def report(self, kind, data):
        self.reported.append((kind, data))


def record(cycle: int) -> CycleRecord:
    return CycleRecord(cycle, cycle * 0.005, "a", np.zeros(1), np.zeros(1), np.zeros(1), True)


def test_a_stream_that_falls_behind_reports_the_cycles_it_dropped():
    sink, runner = Blocked(), Runner()
    stream = TopicStream(Topics(), sink, "test", 0.01, DROP)
    sink.release.set()
    stream.on_start(runner)                     # the opening messages go through
    sink.entered.clear()
    sink.release.clear()
    for cycle in range(3):                      # 0.01 s: 0, 1, 2 handed over
        stream.on_cycle(record(cycle))
    sink.entered.wait()                         # writing them, blocked
    for cycle in range(3, 3 + 2 * 1000):
        stream.on_cycle(record(cycle))
    sink.release.set()
    stream.on_stop(None)
    [(kind, data)] = runner.reported[:1]
    assert kind == "dropped" and data["writer"] == "test" and data["from"] == 0.015
    assert stream.dropped == sum(d["cycles"] for _, d in runner.reported)
    written = [time for topic, time, _ in sink.messages if topic == "/cycle"]
    assert written[:3] == [0, 1, 2] and len(written) + stream.dropped == 2003


def test_a_stream_that_falls_behind_drops_cycles_but_never_events():
    sink, runner = Blocked(), Runner()
    stream = TopicStream(Topics(), sink, "test", 0.01, DROP)
    sink.release.set()
    stream.on_start(runner)
    sink.entered.clear()
    sink.release.clear()
    for cycle in range(3):
        stream.on_cycle(record(cycle))
    sink.entered.wait()                         # writing 0, 1, 2, blocked
    for cycle in range(3, 2003):
        if cycle % 100 == 0:
            stream.on_event(Event("transition", cycle * 0.005, cycle, {"from": "a", "to": "b"}))
        stream.on_cycle(record(cycle))
    sink.release.set()
    stream.on_stop(None)
    assert stream.dropped > 1000
    events = [time for topic, time, _ in sink.messages if topic == "/event"]
    assert events == [cycle * 0.005 for cycle in range(100, 2003, 100)]


class Keep(Observer):
    def __init__(self):
        self.records = []

    def on_cycle(self, record):
        self.records.append(record)


def test_packed_cycles_come_back_as_they_were():
    mission = load_mission("missions/pickup.mission")
    runner = mission.runner()
    keep = Keep()
    runner.add_observer(keep)
    runner.run(duration=6.0)
    batch = keep.records[1020:1040]             # the part attached at 5.155 s
    copies = {task.name: task.detached() for task in runner.tasks()}
    for before, after in zip(batch, unpack(pack(batch), copies), strict=True):
        for field in ("cycle", "time", "state", "solved", "compute_time", "cycle_time"):
            assert getattr(before, field) == getattr(after, field)
        for field in ("q", "positions", "command"):
            np.testing.assert_array_equal(getattr(before, field), getattr(after, field))
        assert before.body_poses.keys() == after.body_poses.keys()
        for body, pose in before.body_poses.items():
            np.testing.assert_array_equal(pose, after.body_poses[body])
        assert sorted(v.name for v in before.tasks) == sorted(v.name for v in after.tasks)


@pytest.mark.parametrize("mission, duration", [
    ("pickup.mission", 12.0),             # joint_position, body_pose, gaze on a part
    ("pickup_cascade.mission", 6.0),      # the head's views come from its own thread
    ("panda_press.mission", 6.0),         # body_position, body_orientation, body_force
    ("two_parts.mission", 6.0),
])
def test_the_writing_process_computes_the_views_the_run_computes(mission, duration):
    """The log's writing process gets each task's samples, target and the poses its
    view reads, and computes the views with pickled copies of the tasks: they are the
    views the run itself computes."""
    runner = load_mission(MISSIONS / mission).runner()
    records = Keep()
    runner.add_observer(records)
    runner.run(duration=duration)
    copies = pickle.loads(pickle.dumps({task.name: task.detached()
                                        for task in runner.tasks()}))
    kinds = set()
    for start in range(0, len(records.records), 40):
        batch = records.records[start:start + 40]
        sent = pickle.loads(pickle.dumps(pack(batch)))
        for record, received in zip(batch, unpack(sent, copies), strict=True):
            assert received.cycle == record.cycle
            twins = {twin.name: twin for twin in received.tasks}
            assert len(twins) == len(record.tasks)
            for view in record.tasks:
                twin = twins[view.name]
                kinds.add(view.kind)
                assert (twin.name, twin.kind, twin.body) == (view.name, view.kind, view.body)
                for field in ("error", "position_error", "orientation_error", "target",
                              "reference"):
                    assert np.array_equal(getattr(twin, field), getattr(view, field),
                                          equal_nan=True), (record.cycle, view.name, field)
    assert len(kinds) >= 2
