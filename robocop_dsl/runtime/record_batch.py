"""Cycle records packed for another process: a batch of
:class:`~robocop_dsl.runtime.CycleRecord` s as a few arrays (records holding many
small arrays pickle slowly, array after array), and back. The task views are computed
when packing; the micro steps are left out (no writer reads them)."""

from __future__ import annotations

import numpy as np

from .records import CycleRecord, TaskView

_TASK_FIELDS = ("error", "position_error", "orientation_error")


def pack(records: list) -> dict:
    """A batch of consecutive records as arrays (and lists of their states and vars)."""
    rows = len(records)
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
        "tasks": {},
    }
    for row, record in enumerate(records):
        for view in record.tasks:
            task = batch["tasks"].get(view.name)
            if task is None:
                task = batch["tasks"][view.name] = {
                    field: np.full(rows, np.nan) for field in _TASK_FIELDS}
                task.update(kind=view.kind, body=view.body, target=[None] * rows,
                            reference=[None] * rows)
            for field in _TASK_FIELDS:
                task[field][row] = getattr(view, field)
            task["target"][row], task["reference"][row] = view.target, view.reference
    for task in batch["tasks"].values():
        for field in ("target", "reference"):
            task[field] = _stacked(task[field])
    return batch


def unpack(batch: dict) -> list:
    """The records of a :func:`pack` ed batch."""
    records = []
    tasks = [(name, task["kind"], task["body"], task["error"].tolist(),
              _rows(task["target"]), _rows(task["reference"]), _present(task["reference"]),
              task["position_error"].tolist(), task["orientation_error"].tolist())
             for name, task in batch["tasks"].items()]
    bodies, wrenches = _measured(batch["bodies"]), _measured(batch["wrenches"])
    variables = batch["variables"].items()
    columns = (batch["cycle"].tolist(), batch["time"].tolist(), batch["state"],
               list(batch["q"]), list(batch["positions"]), list(batch["command"]),
               batch["solved"].tolist(), batch["compute_time"].tolist(),
               batch["cycle_time"].tolist())
    for row, (cycle, time, state, q, positions, command, solved, compute_time,
              cycle_time) in enumerate(zip(*columns)):
        views = tuple(
            TaskView(name, kind, body, error[row], target[row], reference[row],
                     position_error[row], orientation_error[row])
            for name, kind, body, error, target, reference, present, position_error,
            orientation_error in tasks if present[row])
        records.append(CycleRecord(
            cycle, time, state, q, positions, command, solved, views,
            {key: values[row] for key, values, present in bodies if present[row]},
            compute_time, cycle_time,
            wrenches={key: values[row] for key, values, present in wrenches if present[row]},
            variables={name: values[row] for name, values in variables
                       if values[row] is not None}))
    return records


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
    """``(shape, array)``: the values (``None`` where the task was disabled) stacked
    when they all have one shape; else the list as is."""
    shapes = {np.shape(value) for value in values if value is not None}
    if len(shapes) != 1:
        return (None, values)
    [shape] = shapes
    array = np.full((len(values), *shape), np.nan)
    present = np.array([value is not None for value in values])
    array[present] = [value for value in values if value is not None]
    return (shape, (array, present))


def _present(stacked: tuple) -> list:
    """Whether each row of a :func:`_stacked` column has a value."""
    shape, values = stacked
    return [value is not None for value in values] if shape is None else values[1].tolist()


def _rows(stacked: tuple) -> list:
    """The rows of a :func:`_stacked` column."""
    shape, values = stacked
    return values if shape is None else list(values[0])
