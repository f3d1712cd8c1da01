"""Writing a run to a folder: ``events.jsonl`` (one JSON object per line, written as
they happen) and ``timeseries.parquet`` (one row per cycle, one column per signal).

The time series columns: ``cycle``, ``time`` [s], ``state`` (the active configuration:
leaf state paths joined by `` | ``), ``solved``,
``q.JOINT`` [rad or m], ``command.JOINT`` [rad/s or m/s], ``error.TASK`` (norm, m or
rad), ``reference.TASK.I`` (the task's interpolated reference, component I; poses as
x, y, z [m] then a rotation vector [rad]),
``cycle_time`` and ``compute_time`` [s]. Read it with ``pandas.read_parquet`` or
``pyarrow.parquet.read_table(...).column("time").to_numpy()``.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .records import CycleRecord, Event, Observer

EVENTS = "events.jsonl"
TIMESERIES = "timeseries.parquet"


class RunLogger(Observer):
    """An observer that records every cycle in memory and every event on disk at once.

    The time series is written when the run stops, whatever the reason (success,
    failure, fault, interruption), so no cycle is lost.
    """

    def __init__(self, folder: str | Path, joint_names: list):
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.joint_names = list(joint_names)
        self._events = open(self.folder / EVENTS, "w", encoding="utf-8")
        self._records: list[CycleRecord] = []

    def on_cycle(self, record: CycleRecord) -> None:
        self._records.append(record)

    def on_event(self, event: Event) -> None:
        self._events.write(json.dumps(event.to_json(), default=_plain) + "\n")
        self._events.flush()

    def on_stop(self, result) -> None:
        self._events.close()
        self.write_timeseries()

    def write_timeseries(self) -> Path:
        import pyarrow as pa
        import pyarrow.parquet as pq

        records = self._records
        columns: dict = {
            "cycle": np.array([r.cycle for r in records], dtype=np.int64),
            "time": np.array([r.time for r in records]),
            "state": pa.array([r.state for r in records]).dictionary_encode(),
            "solved": np.array([r.solved for r in records], dtype=bool),
        }
        positions = _stack([r.positions for r in records], len(self.joint_names))
        commands = _stack([r.command for r in records], len(self.joint_names))
        for index, joint in enumerate(self.joint_names):
            columns[f"q.{joint}"] = positions[:, index]
        for index, joint in enumerate(self.joint_names):
            columns[f"command.{joint}"] = commands[:, index]
        views = [{v.name: v for v in r.tasks} for r in records]
        tasks = list(dict.fromkeys(name for by_name in views for name in by_name))
        for task in tasks:
            columns[f"error.{task}"] = np.array(
                [v[task].error if task in v else np.nan for v in views])
            flat = [reference_vector(v[task].reference) if task in v else None for v in views]
            size = max((len(f) for f in flat if f is not None), default=0)
            references = _stack(flat, size)
            for component in range(size):
                columns[f"reference.{task}.{component}"] = references[:, component]
        columns["cycle_time"] = np.array([r.cycle_time for r in records])
        columns["compute_time"] = np.array([r.compute_time for r in records])
        path = self.folder / TIMESERIES
        pq.write_table(pa.table(columns), path)
        return path


def reference_vector(reference: np.ndarray) -> np.ndarray:
    """A logged reference: 4x4 poses as position [m] then rotation vector [rad]."""
    reference = np.asarray(reference, dtype=float)
    if reference.shape != (4, 4):
        return reference.ravel()
    import pinocchio as pin

    return np.concatenate([reference[:3, 3], pin.log3(reference[:3, :3])])


def _stack(rows: list, width: int) -> np.ndarray:
    out = np.full((len(rows), width), np.nan)
    for index, row in enumerate(rows):
        if row is not None and len(row) == width:
            out[index] = row
    return out


def _plain(value):
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    return str(value)


def read_events(folder: str | Path) -> list:
    """The events of a logged run, as dictionaries."""
    lines = (Path(folder) / EVENTS).read_text(encoding="utf-8").splitlines()
    return [json.loads(line) for line in lines if line.strip()]


def read_timeseries(folder: str | Path) -> dict:
    """The time series of a logged run: column name -> numpy array."""
    import pyarrow.parquet as pq

    table = pq.read_table(Path(folder) / TIMESERIES)
    return {name: table.column(name).to_numpy(zero_copy_only=False)
            for name in table.column_names}
