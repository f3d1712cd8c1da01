"""Writing a run to a folder: ``events.jsonl`` (one JSON object per line, written as
they happen) and ``timeseries.parquet`` (one row per cycle, one column per signal).

The time series columns: ``cycle``, ``time`` [s], ``state`` (the active configuration:
leaf state paths joined by `` | ``), ``solved``,
``q.JOINT`` [rad or m], ``command.JOINT`` [rad/s or m/s], ``error.TASK`` (norm, m or
rad, N for a force task; NaN while the task is disabled; a pose task's parts also as
``error.TASK.position`` [m] and ``error.TASK.orientation`` [rad]; each error field's
``unit`` metadata says ``m``, ``rad``, ``m+rad`` or ``N``), ``reference.TASK.I`` (the task's interpolated
reference, component I; poses as x, y, z [m] then a rotation vector [rad]),
``pose.BODY.x|y|z`` [m] and ``pose.BODY.qx|qy|qz|qw`` (the world pose of each free
body, as physics put it), ``force.BODY.x|y|z`` [N] and ``torque.BODY.x|y|z`` [N m] (each
force sensor's reading: what the body exerts on the environment, world frame, torque
about the body's origin; NaN while the driver measures none; the fields' ``unit``
metadata says ``N`` or ``Nm``), ``var.NAME`` (each var's value, SI; a position as
``var.NAME.x|y|z``; NaN until assigned; the field's ``unit`` metadata gives its unit),
``cycle_time`` and ``compute_time`` [s]. The schema's metadata ``joint_groups`` lists the
world's joint groups made of logged joints (``plot`` draws a panel per group). Read it with :func:`read_timeseries`,
``pandas.read_parquet`` or ``pyarrow.parquet.read_table(...)``.

The time series is streamed: every second of mission time a writer thread turns the
cycles into one row group and writes it to ``timeseries.parts/`` as a file of its own
(written under a temporary name, then renamed), so memory stays flat and a killed run
keeps every row group but the one in progress. The writer also keeps the row groups
it wrote and joins them, ten seconds of mission time at a time, into one row group of
``timeseries.parquet`` (written as :data:`JOINING` until the run stops; then it is
completed and renamed, and the parts are removed). :func:`read_timeseries` reads
either. pyarrow is imported and the schema made before the first cycle; in a real-time
run, a writer that falls :data:`BACKLOG` row groups behind drops the oldest (a
``dropped`` event says which cycles) rather than hold up the loop; in a headless run,
the loop waits for it (:mod:`~robocop_dsl.runtime.writer_thread`).
"""

from __future__ import annotations

import io
import json
import math
import os
import shutil
from pathlib import Path

import numpy as np

from ..diagnostics import RobocopError
from .records import CycleRecord, Event, Observer
from .run_info import RunInfo
from .writer_thread import BATCH, WriterThread

EVENTS = "events.jsonl"
TIMESERIES = "timeseries.parquet"
PARTS = "timeseries.parts"
JOINING = "timeseries.parquet.tmp"
GROUP_DURATION = 1.0
"""Mission time [s] per row group."""
JOINED_GROUPS = 10
"""Row group files per row group of the joined ``timeseries.parquet`` (what the end of
a run has left to join at most)."""
DEFAULT_ROWS = 200
"""Rows per row group when the run's period is not known."""
BACKLOG = 4
"""Row groups waiting for the writer thread at most."""


class RunLogger(Observer):
    """An observer that writes every event at once and the time series in row groups,
    from a writer thread, while the run goes; whatever ends the run, :meth:`on_stop`
    writes the last rows and joins the row groups into one file.

    Args:
        folder: The log folder (made if missing).
        joint_names: The controlled joints, in command order.
        policy: What the writer does when :data:`BACKLOG` row groups wait
            (:mod:`~robocop_dsl.runtime.writer_thread`): ``drop`` the oldest (a real-time
            run), write them all while the loop waits (``batch``, a headless run), or
            make the caller ``wait``.

    Attributes:
        dropped: How many cycles the writer dropped.
    """

    def __init__(self, folder: str | Path, joint_names: list, policy: str = BATCH):
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.joint_names = list(joint_names)
        self.policy = policy
        self._events = open(self.folder / EVENTS, "w", encoding="utf-8")
        self._batch: list[CycleRecord] = []
        self._rows = DEFAULT_ROWS
        self._runner = None
        self._tasks: dict | None = None
        self._units: dict = {}
        self._kinds: dict = {}
        self._groups = 0
        self._unjoined: list = []
        self._joined = None
        self._writer: WriterThread | None = None
        self._schema = None
        self._bodies: list = []
        self._sensors: list = []
        self._variables: dict = {}
        self._joint_groups: dict = {}
        self._report = None
        self.dropped = 0
        warm_up()

    def on_start(self, runner) -> None:
        """Size the row groups to the run's period, give every task of the run its
        columns (else they come from the first row group's enabled tasks), make the
        schema and start the writer. ``runner``: the run, or its
        :class:`~robocop_dsl.runtime.run_info.RunInfo`."""
        info = RunInfo.of(runner)
        self._runner = runner
        self._rows = max(1, round(GROUP_DURATION / info.time_step))
        self._tasks = {name: task.width for name, task in info.tasks.items()}
        self._units = {name: task.unit for name, task in info.tasks.items()}
        self._kinds = {name: {"kind": task.kind, "body": task.body}
                       for name, task in info.tasks.items()}
        self._bodies = list(info.free_bodies)
        self._sensors = list(info.sensors)
        self._joint_groups = dict(info.joint_groups)
        self._variables = dict(info.variables)
        self._report = info.report
        self._open([])

    def on_cycle(self, record: CycleRecord) -> None:
        self._batch.append(record)
        if len(self._batch) >= self._rows:
            self._hand_over()
        if self._writer is not None:
            self._writer.loop_sleeps(getattr(self._runner, "next_cycle_at", None))

    def on_event(self, event: Event) -> None:
        self._events.write(event_json(event) + "\n")
        self._events.flush()

    def on_stop(self, result) -> None:
        self._events.close()
        if self._writer is None:
            if self._tasks is None and not self._batch:
                return
            self._open(self._batch)
        try:
            self._writer.close()
            if self._batch:         # the last rows go to the joined file only
                self._unjoined.append(self._table(self._batch))
                self._batch = []
        finally:
            self._writer = None
        self._join_parts()

    def _hand_over(self) -> None:
        if not self._batch:
            return
        if self._writer is None:
            self._open(self._batch)
        batch, self._batch = self._batch, []
        self.dropped += report_dropped(self._report, "time series", self._writer.put(batch))

    def _open(self, records: list) -> None:
        """Fix the columns, clear the folder's time series, start the writer thread."""
        import pyarrow as pa

        if self._tasks is None:
            self._tasks = {v.name: len(reference_vector(v.reference))
                           for r in records for v in r.tasks}
        metadata = {GROUPS_KEY: json.dumps(self._joint_groups)}
        if self._kinds:
            metadata[TASKS_KEY] = json.dumps(self._kinds)
        self._schema = pa.schema(_fields(self.joint_names, self._tasks, self._units,
                                         self._bodies, self._sensors, self._variables),
                                 metadata=metadata)
        shutil.rmtree(self.folder / PARTS, ignore_errors=True)
        (self.folder / PARTS).mkdir()
        (self.folder / TIMESERIES).unlink(missing_ok=True)
        self._writer = WriterThread("run log writer", self._write_group, BACKLOG,
                                    self.policy)

    def _write_group(self, records: list) -> None:
        """In the writer thread: a batch of records becomes a row group file."""
        import pyarrow.parquet as pq

        table = self._table(records)
        final = self.folder / PARTS / f"{self._groups:08d}.parquet"
        temporary = final.with_suffix(".tmp")
        pq.write_table(table, temporary)
        os.replace(temporary, final)
        self._groups += 1
        self._unjoined.append(table)
        if len(self._unjoined) >= JOINED_GROUPS:
            self._writer.turn()
            self._join()

    def _table(self, records: list):
        import pyarrow as pa

        columns: dict = {
            "cycle": np.array([r.cycle for r in records], dtype=np.int64),
            "time": np.array([r.time for r in records]),
            "state": [r.state for r in records],
            "solved": np.array([r.solved for r in records], dtype=bool),
        }
        width = len(self.joint_names)
        positions = _stack([r.positions for r in records], width)
        commands = _stack([r.command for r in records], width)
        for index, joint in enumerate(self.joint_names):
            columns[f"q.{joint}"] = positions[:, index]
        for index, joint in enumerate(self.joint_names):
            columns[f"command.{joint}"] = commands[:, index]
        views = []
        for record in records:
            self._writer.turn()
            views.append({v.name: v for v in record.tasks})
        for task, size in self._tasks.items():
            columns[f"error.{task}"] = np.array(
                [v[task].error if task in v else np.nan for v in views])
            if self._units.get(task) == "m+rad":
                for part in ("position", "orientation"):
                    columns[f"error.{task}.{part}"] = np.array(
                        [getattr(v[task], f"{part}_error") if task in v else np.nan
                         for v in views])
            flat = [reference_vector(v[task].reference) if task in v else None for v in views]
            references = _stack(flat, size)
            for component in range(size):
                columns[f"reference.{task}.{component}"] = references[:, component]
        for body in self._bodies:
            poses = np.array([pose_vector(r.body_poses[body]) for r in records]).reshape(-1, 7)
            for index, component in enumerate(POSE_COMPONENTS):
                columns[f"pose.{body}.{component}"] = poses[:, index]
        for body in self._sensors:
            wrenches = _stack([r.wrenches.get(body) for r in records], 6)
            for index, column in enumerate(wrench_columns(body)):
                columns[column] = wrenches[:, index]
        for name, (size, _) in self._variables.items():
            values = _stack([np.atleast_1d(r.variables[name]) if name in r.variables
                             else None for r in records], size)
            for index, column in enumerate(var_columns(name, size)):
                columns[column] = values[:, index]
        columns["cycle_time"] = np.array([r.cycle_time for r in records])
        columns["compute_time"] = np.array([r.compute_time for r in records])
        return pa.table(columns, schema=self._schema)

    def _join(self) -> None:
        """Write the row groups not joined yet as one row group of the joined file."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        if self._joined is None:
            self._joined = pq.ParquetWriter(self.folder / JOINING, self._schema)
        tables, self._unjoined = self._unjoined, []
        self._joined.write_table(pa.concat_tables(tables) if tables
                                 else self._schema.empty_table())

    def _join_parts(self) -> Path:
        """Complete ``timeseries.parquet`` with the row groups not joined yet, then
        remove the row group files."""
        if self._unjoined or self._joined is None:
            self._join()
        self._joined.close()
        self._joined = None
        path = self.folder / TIMESERIES
        os.replace(self.folder / JOINING, path)
        shutil.rmtree(self.folder / PARTS)
        return path


def warm_up() -> None:
    """Import pyarrow and write a table, so that what it imports on first use (pandas,
    the Parquet writer) is imported before the run, not by the writer thread while the
    loop runs."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    pq.write_table(pa.table({"time": np.zeros(1)}), io.BytesIO())


def event_json(event: Event) -> str:
    """An event as its line of ``events.jsonl`` (without the newline)."""
    return json.dumps(event.to_json(), default=_plain)


def dropped_event(writer: str, records: list) -> dict:
    """The data of a ``dropped`` event: ``writer`` fell behind and dropped the cycles
    of ``records``."""
    first, last = records[0], records[-1]
    return {"writer": writer, "cycles": len(records), "from": first.time, "to": last.time,
            "message": f"{writer} writer fell behind: dropped {len(records)} cycles "
                       f"({first.time:.3f} s to {last.time:.3f} s)"}


def events_of(batch: list) -> list:
    """What of a batch of cycles and events is never dropped: the events."""
    return [item for item in batch if not isinstance(item, CycleRecord)]


def report_dropped(report, writer: str, dropped) -> int:
    """Tell ``report`` (a run's ``report``, or ``None``) that ``writer`` dropped the
    items ``dropped`` (a batch a writer thread let go, or ``None``); returns how many
    cycles they held."""
    records = [item for item in dropped or () if isinstance(item, CycleRecord)]
    if records and report is not None:
        report("dropped", dropped_event(writer, records))
    return len(records)


POSE_COMPONENTS = ("x", "y", "z", "qx", "qy", "qz", "qw")
"""The logged components of a free body's pose: position [m], unit quaternion."""


def pose_vector(pose: np.ndarray) -> np.ndarray:
    """A 4x4 pose as position [m] then quaternion (x, y, z, w)."""
    import pinocchio as pin

    return pin.SE3ToXYZQUAT(pin.SE3(np.asarray(pose, dtype=float)))


def wrench_columns(body: str) -> list:
    """The time series' columns of the force sensor on ``body``: force [N] then torque
    [N m], x, y, z."""
    return [f"{part}.{body}.{axis}" for part in ("force", "torque") for axis in "xyz"]


GROUPS_KEY = b"joint_groups"
"""The time series' schema metadata holding the world's joint groups (JSON: name ->
joints) made of logged joints only, for ``plot``'s panels."""
TASKS_KEY = b"tasks"
"""The time series' schema metadata giving each task's kind (as a
:class:`~robocop_dsl.runtime.TaskView`'s) and body (JSON: name -> ``{kind, body}``), for
``export``'s target markers."""


def declared_groups(world, joints: list) -> dict:
    """The world's declared joint groups whose joints all are among ``joints``."""
    logged = set(joints)
    found = {}
    for name in world.group_names():
        members = list(world.joint_group(name).joints)
        if members and set(members) <= logged:
            found[name] = members
    return found


def var_columns(name: str, size: int) -> list:
    """The time series' columns of a var: ``var.NAME``, or ``var.NAME.x|y|z``."""
    return [f"var.{name}"] if size == 1 else [f"var.{name}.{axis}" for axis in "xyz"]


def _fields(joint_names: list, tasks: dict, units: dict, bodies: list = (),
            sensors: list = (), variables: dict | None = None) -> list:
    """The time series' columns, in order, as pyarrow fields; error fields carry their
    ``unit`` (``units``: task -> unit) as metadata."""
    import pyarrow as pa

    def error(name: str, unit: str | None):
        return pa.field(name, pa.float64(), metadata={"unit": unit} if unit else None)

    fields = [pa.field("cycle", pa.int64()), pa.field("time", pa.float64()),
              pa.field("state", pa.string()), pa.field("solved", pa.bool_())]
    fields += [pa.field(f"q.{joint}", pa.float64()) for joint in joint_names]
    fields += [pa.field(f"command.{joint}", pa.float64()) for joint in joint_names]
    for task, size in tasks.items():
        fields.append(error(f"error.{task}", units.get(task)))
        if units.get(task) == "m+rad":
            fields += [error(f"error.{task}.position", "m"),
                       error(f"error.{task}.orientation", "rad")]
        fields += [pa.field(f"reference.{task}.{i}", pa.float64()) for i in range(size)]
    fields += [pa.field(f"pose.{body}.{component}", pa.float64())
               for body in bodies for component in POSE_COMPONENTS]
    fields += [error(column, "N" if column.startswith("force.") else "Nm")
               for body in sensors for column in wrench_columns(body)]
    fields += [error(column, unit or None) for name, (size, unit) in (variables or {}).items()
               for column in var_columns(name, size)]
    fields += [pa.field("cycle_time", pa.float64()), pa.field("compute_time", pa.float64())]
    return fields


def error_unit(task) -> str | None:
    """The unit of a task's error norm: ``m``, ``rad`` or ``m+rad`` (a pose, or a joint
    group with both kinds of joints), ``N`` (a force); ``None`` for velocity tasks."""
    if task.order != 0:
        return None
    if task.kind == "body_force":
        return "N"
    if task.kind == "joint_position":
        world = task.state.world
        prismatic = {world.joint(joint).type == "prismatic" for joint in task.group.joints}
        return {frozenset({True}): "m", frozenset({False}): "rad"}.get(frozenset(prismatic),
                                                                      "m+rad")
    return {"body_position": "m", "body_pose": "m+rad"}.get(task.kind, "rad")


class UnreadableLog(RobocopError):
    """A log file that cannot be read: not Parquet, cut short or damaged."""


def read_parquet(read, path: Path):
    """``read(path)`` (a pyarrow reader), its failures as :class:`UnreadableLog`."""
    import pyarrow as pa

    try:
        return read(path)
    except (pa.ArrowException, OSError) as error:
        raise UnreadableLog(f"{path}: not a readable Parquet file ({error})") from None


def timeseries_files(folder: str | Path) -> list[Path]:
    """The Parquet files of a logged run's time series: the joined file, else the row
    groups of a killed run. Raises ``FileNotFoundError`` when there are none,
    :class:`UnreadableLog` when the folder cannot be read."""
    folder = Path(folder)
    try:
        if (folder / TIMESERIES).is_file():
            return [folder / TIMESERIES]
        parts = sorted((folder / PARTS).glob("*.parquet")) if folder.is_dir() else []
    except OSError as error:
        raise UnreadableLog(f"{folder}: cannot be read ({error.strerror})") from None
    if not parts:
        raise FileNotFoundError(f"{folder} has neither {TIMESERIES} nor {PARTS}/")
    return parts


LATEST = 2.0 ** 31
"""[s] Mission times are below it (the seconds of a ROS 2 time stamp are an int32)."""
RANGES = {"cycle": (0, np.inf), "time": (0, LATEST)}
"""The range of the time series' ``cycle`` and ``time`` columns (upper bound left out)."""


def check_timeseries(folder: str | Path, columns: tuple = ("time", "state")):
    """The schema of a logged run's time series, checked: every file has the same
    columns, among them ``columns``; every column but ``state`` holds numbers; every
    ``q.JOINT`` has its ``command.JOINT``; ``cycle`` and ``time`` are within
    :data:`RANGES`, the times rising from row to row and every row with a ``state``; its
    ``joint_groups`` and ``tasks`` metadata, when there, are JSON of their shape.

    Raises:
        FileNotFoundError: there is none.
        UnreadableLog: a file is damaged or is not a time series.
    """
    import pyarrow as pa
    import pyarrow.parquet as pq

    files = timeseries_files(folder)
    schema = read_parquet(pq.read_schema, files[0])
    names = schema.names
    missing = [name for name in columns if name not in names] + [
        f"command.{name[2:]}" for name in names
        if name.startswith("q.") and f"command.{name[2:]}" not in names]
    if missing:
        raise UnreadableLog(f"{files[0]}: no column {', '.join(missing)}")
    numeric = (pa.types.is_integer, pa.types.is_floating, pa.types.is_boolean)
    odd = [f"{field.name} ({field.type})" for field in schema if field.name != "state"
           and not any(kind(field.type) for kind in numeric)]
    if odd:
        raise UnreadableLog(f"{files[0]}: columns that are not numbers: {', '.join(odd)}")
    metadata = schema.metadata or {}
    for key, valid in METADATA.items():
        if key in metadata and not _valid_json(metadata[key], valid):
            raise UnreadableLog(f"{files[0]}: its {key.decode()} metadata is damaged")
    ranges = {name: RANGES[name] for name in RANGES if name in names}
    read = list(ranges) + ["state"] * ("state" in names)
    last = -math.inf
    for file in files:
        if not read_parquet(pq.read_schema, file).equals(schema):
            raise UnreadableLog(f"{file}: not the columns of {files[0]}")
        table = read_parquet(lambda path: pq.read_table(path, columns=read), file)
        for name, (low, high) in ranges.items():
            values = table.column(name).to_numpy(zero_copy_only=False).astype(float)
            if not np.all((values >= low) & (values < high)):
                raise UnreadableLog(f"{file}: column {name} holds values that are NaN or "
                                    f"out of [{low:.0f}, {high:.0f})")
        last = _rising(file, table, last)
        if "state" in names and table.column("state").null_count:
            raise UnreadableLog(f"{file}: rows without a state")
    return schema


def _rising(file, table, last: float) -> float:
    """The last time [s] of ``table`` (a time series part whose rows follow one at
    ``last``), its times checked to rise from row to row.

    Raises:
        UnreadableLog: a row's time is not after the one before it.
    """
    if "time" not in table.column_names:
        return last
    times = table.column("time").to_numpy(zero_copy_only=False).astype(float)
    back = np.flatnonzero(np.diff(times, prepend=last) <= 0)
    if back.size:
        row = back[0]
        where = (f"cycle {table.column('cycle')[row].as_py()}" if "cycle" in table.column_names
                 else f"row {row + 1}")
        raise UnreadableLog(f"{file}: time does not rise at {where}: {times[row]:g} s "
                            f"after {times[row - 1] if row else last:g} s")
    return float(times[-1]) if len(times) else last


def _valid_json(text: bytes, valid) -> bool:
    """Whether ``text`` is a JSON object whose every value is ``valid``."""
    try:
        found = json.loads(text)
    except ValueError:
        return False
    return isinstance(found, dict) and all(valid(value) for value in found.values())


METADATA = {
    GROUPS_KEY: lambda joints: isinstance(joints, list)
    and all(isinstance(joint, str) for joint in joints),
    TASKS_KEY: lambda task: isinstance(task, dict) and isinstance(task.get("kind"), str)
    and isinstance(task.get("body"), (str, type(None))),
}
"""The time series' JSON metadata: key -> whether a value of its object is valid."""


def reference_width(task) -> int:
    """How many numbers a task's logged reference has: 6 for an orientation (logged as
    a pose, see :func:`reference_vector`), 3 for a force (its target, whatever axes it
    controls), else the task's dimension."""
    return {"body_orientation": 6, "body_force": 3}.get(task.kind, int(task.dimension))


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


def event_lines(folder: str | Path) -> list:
    """``(line, event)`` for each line of a logged run's ``events.jsonl``; a last line
    cut short by a kill is left out.

    Raises:
        FileNotFoundError: there is none.
        UnreadableLog: it cannot be read, or another line is not an event (a JSON
            object with a string ``kind``, a ``cycle`` and a ``time`` in
            :data:`RANGES`).
    """
    path = Path(folder) / EVENTS
    try:
        lines = path.read_bytes().splitlines()
    except FileNotFoundError:
        raise
    except OSError as error:
        raise UnreadableLog(f"{path}: cannot be read ({error.strerror})") from None
    found = []
    for number, line in enumerate(lines, start=1):
        try:
            text = line.decode("utf-8")
            event = json.loads(text)
        except ValueError:
            if number == len(lines):
                break
            event = None
        if not _is_event(event):
            raise UnreadableLog(f"{path}: line {number} is not an event (a JSON object "
                                "with a kind, a cycle and a time)")
        found.append((text, event))
    return found


def _is_event(event) -> bool:
    if not isinstance(event, dict):
        return False
    kind, time, cycle = event.get("kind"), event.get("time"), event.get("cycle")
    (first, _), (start, end) = RANGES["cycle"], RANGES["time"]
    return (isinstance(kind, str) and isinstance(cycle, int) and cycle >= first
            and isinstance(time, (int, float)) and start <= time < end
            and not isinstance(time, bool))


def read_events(folder: str | Path) -> list:
    """The events of a logged run, as dictionaries (a last line cut short by a kill is
    left out); raises as :func:`event_lines`."""
    return [event for _, event in event_lines(folder)]


def read_timeseries(folder: str | Path) -> dict:
    """The time series of a logged run: column name -> numpy array. A run that was
    killed has no ``timeseries.parquet``: its row groups written so far are read."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    table = pa.concat_tables([read_parquet(pq.read_table, file)
                              for file in timeseries_files(folder)])
    return {name: table.column(name).to_numpy(zero_copy_only=False)
            for name in table.column_names}
