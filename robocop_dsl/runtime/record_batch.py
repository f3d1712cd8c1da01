"""Cycle records packed for another process: a batch of
:class:`~robocop_dsl.runtime.CycleRecord` s as a few arrays (records holding many
small arrays pickle slowly, array after array), and back. The task views are not
computed when packing: the batch carries what was captured for them (each task's
sample and target, and the world poses its view reads), and :func:`unpack` computes
them with copies of the tasks (:meth:`~robocop_dsl.control.Task.detached`). The micro
steps are left out (no writer reads them)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..control.tasks.base import TaskSample
from .records import CycleRecord
from .views import frames_read, resolve_view

_SAMPLE = ("value", "goal", "reference")


def pack(records: list) -> dict:
    """A batch of consecutive records as arrays (and lists of their states and vars)."""
    batch = {
        "cycle": np.array([r.cycle for r in records], dtype=np.int64),
        "time": np.array([r.time for r in records]),
        "state": [r.state for r in records],
        "solved": np.array([r.solved for r in records], dtype=bool),
        "compute_time": np.array([r.compute_time for r in records]),
        "cycle_time": np.array([r.cycle_time for r in records]),
        "q": np.array([r.q for r in records]),
        "positions": np.array([r.positions for r in records]),
        "command": np.array([r.command for r in records]),
        "bodies": _keyed(records, "body_poses", (4, 4)),
        "wrenches": _keyed(records, "wrenches", (6,)),
        "variables": {name: [r.variables.get(name) for r in records]
                      for name in {name for r in records for name in r.variables}},
    }
    batch["tasks"], batch["frames"] = _captured(records)
    return batch


def _captured(records: list) -> tuple[dict, dict]:
    """Per task name, its samples' columns (``captured`` in each row, ``value``,
    ``goal``, ``reference``: poses as 4x4 matrices, and ``target``); per frame id, the
    world poses the views read."""
    rows = len(records)
    tasks: dict = {}
    frames: dict = {}
    for row, record in enumerate(records):
        for task, sample, target, poses in getattr(record.tasks, "captures", ()):
            columns = tasks.get(task.name)
            if columns is None:
                columns = tasks[task.name] = _TaskColumns(rows)
            columns.captured[row] = True
            columns.target[row] = target
            value = sample.value
            if value is None:
                continue
            columns.value[row], columns.goal[row] = value, sample.goal
            columns.reference[row] = sample.reference
            if columns.read is None or columns.read_for is not target:
                columns.read_for, columns.read = target, frames_read(task, target)
            for frame_id in columns.read:
                column = frames.get(frame_id)
                if column is None:
                    column = frames[frame_id] = [None] * rows
                if column[row] is None:
                    column[row] = poses[frame_id].homogeneous
    return ({name: columns.packed() for name, columns in tasks.items()},
            {frame_id: _stacked(column) for frame_id, column in frames.items()})


class _TaskColumns:
    """One task's captures in a batch, row by row (``None`` where it has none), and the
    frames its latest target reads."""

    __slots__ = ("captured", "target", "value", "goal", "reference", "read_for", "read")

    def __init__(self, rows: int):
        self.captured = [False] * rows
        self.target = [None] * rows
        self.value, self.goal, self.reference = [None] * rows, [None] * rows, [None] * rows
        self.read_for = self.read = None

    def packed(self) -> dict:
        """The columns as :func:`_captured` gives them."""
        columns = {"captured": np.array(self.captured, dtype=bool), "target": self.target}
        for field in _SAMPLE:
            values = getattr(self, field)
            placed = isinstance(next((v for v in values if v is not None), None), pin.SE3)
            columns[field] = (placed, _stacked([value.homogeneous if placed and value is not None
                                                else value for value in values]))
        return columns


def unpack(batch: dict, tasks: dict) -> list:
    """The records of a :func:`pack` ed batch, their task views computed with
    ``tasks`` (by name: the run's tasks, or copies of them)."""
    records = []
    captured = [(tasks[name], columns["captured"].tolist(), columns["target"],
                 *(_samples(*columns[field]) for field in _SAMPLE))
                for name, columns in batch["tasks"].items()]
    frames = [(frame_id, _rows(stacked), _present(stacked))
              for frame_id, stacked in batch["frames"].items()]
    bodies, wrenches = _measured(batch["bodies"]), _measured(batch["wrenches"])
    variables = batch["variables"].items()
    columns = (batch["cycle"].tolist(), batch["time"].tolist(), batch["state"],
               list(batch["q"]), list(batch["positions"]), list(batch["command"]),
               batch["solved"].tolist(), batch["compute_time"].tolist(),
               batch["cycle_time"].tolist())
    for row, (cycle, time, state, q, positions, command, solved, compute_time,
              cycle_time) in enumerate(zip(*columns)):
        poses = {frame_id: pin.SE3(values[row]) for frame_id, values, present in frames
                 if present[row]}
        views = tuple(
            resolve_view(task, TaskSample(cycle, value[row], goal[row], reference[row]),
                         target[row], poses)
            for task, present, target, value, goal, reference in captured if present[row])
        records.append(CycleRecord(
            cycle, time, state, q, positions, command, solved, views,
            {key: values[row] for key, values, present in bodies if present[row]},
            compute_time, cycle_time,
            wrenches={key: values[row] for key, values, present in wrenches if present[row]},
            variables={name: values[row] for name, values in variables
                       if values[row] is not None}))
    return records


def _samples(placed: bool, stacked: tuple) -> list:
    """The rows of a packed sample column (``None`` where there is none), as ``pin.SE3``
    when ``placed`` (the column holds poses)."""
    rows, present = _rows(stacked), _present(stacked)
    if placed:
        return [pin.SE3(value) if here else None for value, here in zip(rows, present)]
    return [value if here else None for value, here in zip(rows, present)]


def _keyed(records: list, attribute: str, shape: tuple) -> dict:
    """Each key of the records' ``attribute`` mappings -> its values, NaN where a
    record has none."""
    keys = {key for record in records for key in getattr(record, attribute)}
    out = {key: np.full((len(records), *shape), np.nan) for key in keys}
    for row, record in enumerate(records):
        for key, value in getattr(record, attribute).items():
            out[key][row] = value
    return out


def _measured(keyed: dict) -> list:
    """``(key, rows, present)`` of each key of a :func:`_keyed` mapping: its rows and
    whether each has a value (not all NaN)."""
    return [(key, list(values),
             (~np.isnan(values.reshape(len(values), -1)).all(axis=1)).tolist())
            for key, values in keyed.items()]


def _stacked(values: list):
    """``(shape, (array, present))``: the values (``None`` where a row has none) stacked
    into one array, NaN where absent, when they all have one shape; else ``(None,
    values)``."""
    present = np.array([value is not None for value in values], dtype=bool)
    try:
        kept = np.array([value for value in values if value is not None], dtype=float)
    except (ValueError, TypeError):     # values of different shapes, or not numbers
        return (None, values)
    if not len(kept):
        return (None, values)
    array = np.full((len(values), *kept.shape[1:]), np.nan)
    array[present] = kept
    return (kept.shape[1:], (array, present))


def _present(stacked: tuple) -> list:
    """Whether each row of a :func:`_stacked` column has a value."""
    shape, values = stacked
    return [value is not None for value in values] if shape is None else values[1].tolist()


def _rows(stacked: tuple) -> list:
    """The rows of a :func:`_stacked` column."""
    shape, values = stacked
    return values if shape is None else list(values[0])
