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
    tasks = batch["tasks"]
    for row in range(len(batch["cycle"])):
        views = tuple(
            TaskView(name, task["kind"], task["body"], task["error"][row],
                     _item(task["target"], row), _item(task["reference"], row),
                     task["position_error"][row], task["orientation_error"][row])
            for name, task in tasks.items() if _present(task["reference"], row))
        records.append(CycleRecord(
            int(batch["cycle"][row]), float(batch["time"][row]), batch["state"][row],
            batch["q"][row], batch["positions"][row], batch["command"][row],
            bool(batch["solved"][row]), views, _row(batch["bodies"], row),
            float(batch["compute_time"][row]), float(batch["cycle_time"][row]),
            wrenches=_row(batch["wrenches"], row),
            variables={name: values[row] for name, values in batch["variables"].items()
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


def _row(keyed: dict, row: int) -> dict:
    return {key: values[row] for key, values in keyed.items() if not np.isnan(values[row]).all()}


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


def _present(stacked: tuple, row: int) -> bool:
    shape, values = stacked
    return values[row] is not None if shape is None else bool(values[1][row])


def _item(stacked: tuple, row: int):
    shape, values = stacked
    return values[row] if shape is None else values[0][row]
