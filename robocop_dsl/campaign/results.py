"""The results table: one row per job, sorted by job, written as Parquet.

Columns (SI units):

- ``job``, ``mission``, ``mission_file`` (its path as the campaign names it),
  ``variant``, ``sample``: which run;
- ``solver``, ``hierarchy``, ``time_step`` [s]: the controller settings it ran with;
- ``outcome``: the run's (``success``, ``failure``, ``stopped``, ``fault``,
  ``interrupted``), or ``error`` (the job raised) or ``timeout`` (past its budget);
- ``final_state``, ``mission_time`` [s], ``cycles``, ``qp_failures``;
- ``worst_task_error`` [m or rad]: the largest task error in the last cycle;
- ``min_limit_margin`` [rad or m] and ``limit_joint``: the closest any controlled joint
  came to one of its position limits during the run, and which joint;
- ``wall_time`` [s]: how long the job took where it ran (the only column that changes
  from one sweep of a campaign to the next);
- ``message``: why the run ended;
- then the sampled conditions: ``BODY.x``, ``BODY.y``, ``BODY.z`` [m] for moved bodies
  and ``initial.JOINT`` [rad or m] for the start posture of noisy joints.

The file's metadata keeps the campaign's name, path, seed and sample count.
"""

from __future__ import annotations

import os
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from ..diagnostics import RobocopError

COLUMNS = (
    ("job", pa.int64()), ("mission", pa.string()), ("mission_file", pa.string()),
    ("variant", pa.string()), ("sample", pa.int64()), ("solver", pa.string()),
    ("hierarchy", pa.string()), ("time_step", pa.float64()), ("outcome", pa.string()), ("final_state", pa.string()),
    ("mission_time", pa.float64()), ("cycles", pa.int64()), ("qp_failures", pa.int64()),
    ("worst_task_error", pa.float64()), ("min_limit_margin", pa.float64()),
    ("limit_joint", pa.string()), ("wall_time", pa.float64()), ("message", pa.string()),
)
IDENTIFYING = ("job", "mission", "variant", "sample", "outcome")
"""Columns every results table has had: a table with them is one to write over."""
VOLATILE = ("wall_time",)
"""Columns that depend on the machine and the moment, not on the campaign."""


def results_table(rows: list, metadata: dict | None = None) -> pa.Table:
    """The rows (dicts from :func:`~.worker.run_job`) as a table sorted by job.

    Missing values are nulls; condition columns follow the fixed ones in the order they
    first appear in job order.
    """
    rows = sorted(rows, key=lambda row: row["job"])
    fixed = dict(COLUMNS)
    extra = list(dict.fromkeys(k for row in rows for k in row if k not in fixed))
    schema = pa.schema([*COLUMNS, *((name, pa.float64()) for name in extra)],
                       metadata={k: str(v) for k, v in (metadata or {}).items()})
    data = {name: [row.get(name) for row in rows] for name in schema.names}
    return pa.table(data, schema=schema)


class OutputError(RobocopError):
    """The results table cannot be written where asked."""


def check_output(path: str | Path, replace: bool = False) -> Path:
    """Make sure a results table can be written at ``path``, before any job runs: its
    folder is made and written to, and a file already there is a results table (see
    :func:`is_results_table`) or ``replace`` allows writing over it.

    Raises:
        OutputError: why it cannot be written.
    """
    path = Path(path)
    if path.is_dir():
        raise OutputError("it is a folder")
    if path.exists() or path.is_symlink():
        if not path.is_file():
            raise OutputError("it is not a regular file")
        if not replace and not is_results_table(path):
            raise OutputError("the file exists and is not a results table: give "
                              "--replace to write over it")
    folder = next((p for p in path.parents if p.exists()), None)
    if folder is not None and not folder.is_dir():
        raise OutputError(f"'{folder}' is not a folder")
    probe = _temporary(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        probe.open("xb").close()
        probe.unlink()
    except OSError as error:
        raise OutputError(error.strerror or str(error)) from None
    return path


def is_results_table(path: str | Path) -> bool:
    """Whether ``path`` is a Parquet file with the results table's columns and a
    campaign in its metadata: what :func:`write_results` writes."""
    try:
        schema = pq.read_schema(path)
    except (OSError, ValueError, pa.ArrowException):
        return False
    return b"campaign" in (schema.metadata or {}) and set(IDENTIFYING) <= set(schema.names)


def write_results(table: pa.Table, path: str | Path) -> Path:
    """Write ``table`` as Parquet at ``path`` (folders created); return the path. It is
    written beside it first, so a file already there is only ever replaced whole."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = _temporary(path)
    try:
        pq.write_table(table, temporary)
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)
    return path


def _temporary(path: Path) -> Path:
    """A hidden file beside ``path``, of this process."""
    return path.with_name(f".{path.name}.{os.getpid()}.tmp")


def read_results(path: str | Path) -> pa.Table:
    """Read a results table written by :func:`write_results`."""
    return pq.read_table(path)


def comparable(table: pa.Table) -> pa.Table:
    """``table`` without its :data:`VOLATILE` columns and metadata, for comparing sweeps."""
    kept = [name for name in table.column_names if name not in VOLATILE]
    return table.select(kept).replace_schema_metadata(None)
