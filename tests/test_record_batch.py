"""The log's writing process gets the cycles packed, with what was captured for the
task views (samples, targets, the poses the views read), and computes the views with
pickled copies of the tasks: they are the views the run itself computes."""

import pickle

import numpy as np
import pytest

from conftest import MISSIONS
from robocop_dsl.runtime import Observer, load_mission
from robocop_dsl.runtime.record_batch import pack, unpack

BATCH = 40       # cycles per packed batch


class Records(Observer):
    def __init__(self):
        self.records = []

    def on_cycle(self, record):
        self.records.append(record)


@pytest.mark.parametrize("mission, duration", [
    ("pickup.mission", 12.0),             # joint_position, body_pose, gaze on a part
    ("pickup_cascade.mission", 6.0),      # the head's views come from its own thread
    ("panda_press.mission", 6.0),         # body_position, body_orientation, body_force
    ("two_parts.mission", 6.0),
])
def test_the_writing_process_computes_the_views_the_run_computes(mission, duration):
    runner = load_mission(MISSIONS / mission).runner()
    records = Records()
    runner.add_observer(records)
    runner.run(duration=duration)
    copies = pickle.loads(pickle.dumps({task.name: task.detached()
                                        for task in runner.tasks()}))
    kinds = set()
    for start in range(0, len(records.records), BATCH):
        batch = records.records[start:start + BATCH]
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
