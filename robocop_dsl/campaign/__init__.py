"""Campaigns: many missions, on world variants, under randomised conditions, run on
worker processes of this machine, on a running Dask scheduler's workers, or in this
process alone.

``load_campaign`` reads, checks and expands a campaign file into jobs; ``open_engine``
starts the workers (each loads the campaign's missions once) and ``sweep`` runs the
jobs on them; ``results_table`` and ``write_results`` make the Parquet table;
``print_summary`` tells what failed and how to rerun it.
"""

from .engine import DaskEngine, SerialEngine, open_engine, sweep
from .jobs import Campaign, Job, load_campaign
from .pool import PoolEngine, WorkerStartError
from .reader import read_campaign
from .results import OutputError, check_output, comparable, is_results_table, read_results, \
    results_table, write_results
from .sampling import Conditions, draw_conditions
from .summary import print_summary, rerun_command
from .worker import PreparedRun, WorkerCache, prepare, run_job

__all__ = ["Campaign", "Conditions", "DaskEngine", "Job", "OutputError", "PoolEngine",
           "PreparedRun", "SerialEngine", "WorkerCache", "WorkerStartError", "check_output",
           "comparable", "draw_conditions", "is_results_table", "load_campaign",
           "open_engine", "prepare", "print_summary", "read_campaign", "read_results",
           "rerun_command", "results_table", "run_job", "sweep", "write_results"]
