"""A log folder (``events.jsonl`` and the time series) as ``run.mcap``: the topics a
run writes while it goes, rebuilt from what the log keeps.

The world is the one the ``start`` event names (or one given, for logs that do not say).
Joints the log does not have stay at the world's initial posture; a body the run
attached or placed (``action`` events) moves as it did; free bodies are where their
``pose.BODY.*`` columns put them. ``/mission/targets`` shows each task's interpolated
reference only (the log keeps no targets), and only for logs that name their tasks'
kinds (its ``tasks`` metadata).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from ..diagnostics import RobocopError
from ..runtime.log import (EVENTS, PARTS, POSE_COMPONENTS, TASKS_KEY, TIMESERIES,
                           check_timeseries, event_lines, read_parquet, timeseries_files,
                           wrench_columns)
from ..runtime.records import CycleRecord, TaskView
from .frames import quaternion_matrices
from .mcap_file import MCAP_FILE, McapFile
from .stream import MCAP_TF_PERIOD
from .topics import RunTopics

ROWS = 1000
"""Time series rows read at a time."""
COLUMNS = ("cycle", "time", "state", "solved")
"""The time series columns an export needs (with ``command.JOINT`` for each ``q.JOINT``)."""


class ExportError(RobocopError):
    """A log that cannot be exported: no time series, no world."""


def export_mcap(folder: str | Path, output: str | Path | None = None,
                world=None, replace: bool = False) -> Path:
    """Write the MCAP of the log in ``folder``; return its path.

    Args:
        folder: The folder given to ``run --log``.
        output: Where to write it (default ``FOLDER/run.mcap``).
        world: The run's :class:`~robocop_dsl.world.World`, for logs whose ``start``
            event does not name it (default: the one it names).
        replace: Write over ``output`` when it exists (a run's own ``run.mcap`` has
            the targets an export cannot rebuild).

    Raises:
        ExportError: no folder, no events or time series in it, no world, a world
            without the log's joints, ``output`` exists (without ``replace``) or
            cannot be written.
        UnreadableLog: a damaged log: ``events.jsonl`` or a time series file (see
            :func:`~robocop_dsl.runtime.log.check_timeseries`). Nothing is written then.
        DiagnosticError: the world named by the log does not load.
    """
    folder = Path(folder)
    if not os.path.isdir(folder):
        raise ExportError(f"{folder}: no such folder" if not os.path.exists(folder) else
                          f"{folder}: not a folder; give the folder given to 'run --log'")
    lines = _event_lines(folder)
    try:
        schema = check_timeseries(folder, COLUMNS)
    except FileNotFoundError:
        raise ExportError(f"{folder}: no {TIMESERIES} nor {PARTS}/ here; write a log "
                          "with 'robocop-mission run MISSION --log DIR'") from None
    path = Path(output) if output is not None else folder / MCAP_FILE
    if os.path.exists(path) and not replace:
        raise ExportError(f"{path} exists" + (" (the run wrote it, with the targets an "
                                             "export cannot rebuild)" if output is None
                                             else "") +
                          ": give another file with --output, or --replace to write over it")
    if world is None:
        world = _logged_world(folder, lines)
    for _, event in lines:
        if event["kind"] == "action" and not _replayable(event, world):
            raise ExportError(f"{folder}/{EVENTS}: the action at cycle {event['cycle']} "
                              f"cannot be replayed on {world.path}")
    joints = [name[2:] for name in schema.names if name.startswith("q.")]
    missing = [joint for joint in joints if joint not in world.joint_names()]
    if missing:
        raise ExportError(f"{folder}: the log's joints {', '.join(missing)} are not in "
                          f"{world.path}; give the run's world with --world WORLD.yaml")
    metadata = schema.metadata or {}
    kinds = json.loads(metadata[TASKS_KEY]) if TASKS_KEY in metadata else {}
    topics = RunTopics(world, joints, MCAP_TF_PERIOD)
    written = path.with_name(path.name + ".tmp")
    try:
        mcap = McapFile(written, topics.topics)
        mcap.write(topics.opening())
        replay = _Replay(world, joints, kinds, [event for _, event in lines])
        for columns in _rows(folder):
            mcap.write(topics.cycles(replay.records(columns)))
            mcap.checkpoint()
        for line, _ in lines:
            mcap.write(topics.event(line))
        mcap.close()
        os.replace(written, path)
    except OSError as error:
        raise ExportError(f"cannot write {path}: {error.strerror or error}") from None
    finally:
        if os.path.lexists(written):
            os.unlink(written)
    return path


def _event_lines(folder: Path) -> list:
    """``(line, event)`` for each event of ``events.jsonl``."""
    try:
        return event_lines(folder)
    except FileNotFoundError:
        raise ExportError(f"{folder}: no {EVENTS} here; write a log with "
                          "'robocop-mission run MISSION --log DIR'") from None


def _logged_world(folder: Path, lines: list):
    """The world the log's ``start`` event names, loaded."""
    from ..world import load_world

    start = next((event for _, event in lines if event["kind"] == "start"), {})
    if "world" not in start:
        raise ExportError(f"{folder}/{EVENTS} does not say which world the run was on "
                          "(logs written before it did): give it with --world WORLD.yaml")
    if not isinstance(start["world"], str):
        raise ExportError(f"{folder}/{EVENTS}: the start event's world is not a file "
                          "name; give the run's world with --world WORLD.yaml")
    return load_world(start["world"])


def _replayable(event: dict, world) -> bool:
    """Whether an ``action`` event names bodies of ``world`` and, to set a pose, gives
    a position and maybe an orientation."""
    def numbers(value, count: int) -> bool:
        return (isinstance(value, list) and len(value) == count
                and all(isinstance(x, (int, float)) and not isinstance(x, bool)
                        for x in value))

    action = event.get("action")
    return (isinstance(event.get("body"), str) and world.has_body(event["body"])
            and (action != "attach" or isinstance(event.get("to"), str)
                 and world.has_body(event["to"]))
            and (action != "set_pose" or numbers(event.get("position"), 3)
                 and numbers(event.get("orientation", [0, 0, 0, 1]), 4)))


def _rows(folder: Path):
    """The time series, :data:`ROWS` rows at a time: column name -> numpy array."""
    import pyarrow.parquet as pq

    for file in timeseries_files(folder):
        with read_parquet(pq.ParquetFile, file) as parquet:
            batches = parquet.iter_batches(batch_size=ROWS)
            while (batch := read_parquet(lambda _: next(batches, None), file)) is not None:
                yield {name: column.to_numpy(zero_copy_only=False)
                       for name, column in zip(batch.schema.names, batch.columns)}


class _Replay:
    """Cycle records rebuilt from time series rows and the run's ``action`` events."""

    def __init__(self, world, joints: list, kinds: dict, events: list):
        import pinocchio as pin

        from ..world.joint_space import JointSpace

        self._world = world
        self._model = world.model.copy()
        self._data = self._model.createData()
        self._joints = joints
        self._space = JointSpace(self._model, tuple(joints))
        models = [self._model.joints[self._model.getJointId(joint)] for joint in joints]
        self._indices = np.array([index for joint in models
                                  for index in range(joint.idx_q, joint.idx_q + joint.nq)],
                                 dtype=int)
        self._initial = world.initial_configuration()
        self._kinds = {name: kind for name, kind in kinds.items()
                       if kind["kind"] in ("pose", "orientation", "position")}
        self._free = set(world.free_bodies())
        self._sensors = list(world.force_sensors())
        self._actions: dict = {}
        for event in events:
            if event.get("kind") == "action" and event.get("body") not in self._free:
                self._actions.setdefault(event["cycle"], []).append(event)
        self._held: dict = {}       # body -> ("attached", parent frame id, 4x4) | ("placed", 4x4)
        self._pin = pin

    def records(self, columns: dict) -> list:
        """The :class:`~robocop_dsl.runtime.CycleRecord` s of time series rows."""
        rows = len(columns["cycle"])
        positions = np.column_stack([columns[f"q.{joint}"] for joint in self._joints]
                                    ) if self._joints else np.zeros((rows, 0))
        commands = np.column_stack([columns[f"command.{joint}"] for joint in self._joints]
                                   ) if self._joints else np.zeros((rows, 0))
        free = {body: _poses(columns, body) for body in self._free
                if f"pose.{body}.x" in columns}
        records = []
        for row in range(rows):
            q = self._initial.copy()
            q[self._indices] = self._space.coordinates(positions[row])
            cycle = int(columns["cycle"][row])
            bodies = self._moved(cycle, q)
            bodies.update({body: poses[row] for body, poses in free.items()})
            wrenches = {body: np.array([columns[name][row] for name in wrench_columns(body)])
                        for body in self._sensors if f"force.{body}.x" in columns}
            records.append(CycleRecord(
                cycle, float(columns["time"][row]), str(columns["state"][row]), q,
                positions[row], commands[row], bool(columns["solved"][row]),
                self._views(columns, row), bodies, wrenches=wrenches))
        return records

    def _moved(self, cycle: int, q: np.ndarray) -> dict:
        """The world poses of the bodies attached or placed at ``cycle``, after its
        ``attach``, ``detach`` and ``set_pose`` actions."""
        pin, model, data = self._pin, self._model, self._data
        pin.forwardKinematics(model, data, q)

        def pose_of(body: str) -> np.ndarray:
            held = self._held.get(body)
            if held is not None and held[0] == "placed":
                return held[1]
            if held is not None:
                return placement(held[1]) @ held[2]
            return placement(self._world.body_frame_id(body))

        def placement(frame: int) -> np.ndarray:
            return pin.updateFramePlacement(model, data, frame).homogeneous

        for action in self._actions.get(cycle, ()):
            body = action["body"]
            if action["action"] == "attach":
                parent = self._world.body_frame_id(action["to"])
                self._held[body] = ("attached", parent,
                                    np.linalg.inv(placement(parent)) @ pose_of(body))
            elif action["action"] == "detach":
                self._held.pop(body, None)
            elif action["action"] == "set_pose":
                pose = np.eye(4)
                pose[:3, 3] = action["position"]
                if "orientation" in action:
                    pose[:3, :3] = pin.Quaternion(np.array(action["orientation"])).matrix()
                self._held[body] = ("placed", pose)
        return {body: pose_of(body) for body in self._held}

    def _views(self, columns: dict, row: int) -> tuple:
        """The drawn tasks enabled at ``row``, their references in the world."""
        views = []
        for name, kind in self._kinds.items():
            error = columns.get(f"error.{name}")
            if error is None or np.isnan(error[row]):
                continue
            size = 3 if kind["kind"] == "position" else 6
            vector = np.array([columns[f"reference.{name}.{i}"][row] for i in range(size)])
            if kind["kind"] == "position":
                reference = vector
            else:
                reference = np.eye(4)
                reference[:3, :3] = self._pin.exp3(vector[3:])
                reference[:3, 3] = vector[:3]
            views.append(TaskView(name, kind["kind"], kind["body"], float(error[row]),
                                  np.zeros(0), reference))
        return tuple(views)


def _poses(columns: dict, body: str) -> np.ndarray:
    """``N x 4 x 4`` world poses of free ``body`` from its ``pose.BODY.*`` columns."""
    values = np.column_stack([columns[f"pose.{body}.{c}"] for c in POSE_COMPONENTS])
    poses = np.zeros((len(values), 4, 4))
    poses[:, 3, 3] = 1.0
    poses[:, :3, 3] = values[:, :3]
    poses[:, :3, :3] = quaternion_matrices(values[:, 3:])
    return poses
