"""The results table: one row per job, sorted by job, written as Parquet.

Columns (SI units):

- ``job``, ``mission``, ``variant``, ``sample``: which run;
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

from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

COLUMNS = (
    ("job", pa.int64()), ("mission", pa.string()), ("variant", pa.string()),
    ("sample", pa.int64()), ("solver", pa.string()), ("hierarchy", pa.string()),
    ("time_step", pa.float64()), ("outcome", pa.string()), ("final_state", pa.string()),
    ("mission_time", pa.float64()), ("cycles", pa.int64()), ("qp_failures", pa.int64()),
    ("worst_task_error", pa.float64()), ("min_limit_margin", pa.float64()),
    ("limit_joint", pa.string()), ("wall_time", pa.float64()), ("message", pa.string()),
)
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


def write_results(table: pa.Table, path: str | Path) -> Path:
    """Write ``table`` as Parquet at ``path`` (folders created); return the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    pq.write_table(table, path)
    return path


def read_results(path: str | Path) -> pa.Table:
    """Read a results table written by :func:`write_results`."""
    return pq.read_table(path)


def comparable(table: pa.Table) -> pa.Table:
    """``table`` without its :data:`VOLATILE` columns and metadata, for comparing sweeps."""
    kept = [name for name in table.column_names if name not in VOLATILE]
    return table.select(kept).replace_schema_metadata(None)
