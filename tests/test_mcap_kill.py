"""A logged run killed (SIGKILL) 5 s into its mission leaves a ``run.mcap`` that rosbags
reads up to about 4 s (every chunk written so far), and its writing process ends."""

import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

from conftest import write
from robocop_dsl.runtime.log import PARTS
from test_streaming_log import LONG

REPO = Path(__file__).resolve().parent.parent


def wait_for(condition, process: subprocess.Popen) -> None:
    """Poll ``condition()`` until true; fail if the run exits first."""
    while not condition():
        assert process.poll() is None, "the run ended first"
        time.sleep(0.02)


def alive(pid: int) -> bool:
    """Whether process ``pid`` still runs (not gone, not a zombie)."""
    try:
        return "zombie" not in Path(f"/proc/{pid}/status").read_text()
    except FileNotFoundError:
        return False


def children(pid: int) -> list:
    path = Path(f"/proc/{pid}/task/{pid}/children")
    return [int(child) for child in path.read_text().split()] if path.exists() else []


def test_a_killed_run_leaves_an_mcap_readable_up_to_its_last_chunk(tmp_path):
    path = write(tmp_path, "long.mission", LONG)
    log = tmp_path / "log"
    process = subprocess.Popen([sys.executable, "-m", "robocop_dsl", "run", str(path),
                                "--log", str(log)], cwd=REPO, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
    parts = log / PARTS
    wait_for(lambda: parts.is_dir() and len(list(parts.glob("*.parquet"))) >= 5, process)
    writers = children(process.pid)
    process.send_signal(signal.SIGKILL)
    process.wait()
    assert writers, "no writing process"
    for pid in writers:                         # it ends by itself
        while alive(pid):
            time.sleep(0.02)
    with AnyReader([log / "run.mcap"], default_typestore=get_typestore(Stores.EMPTY)) as reader:
        stamps = [time for connection, time, _ in reader.messages()
                  if connection.topic == "/joint_states"]
    assert stamps[-1] >= 4e9
    np.testing.assert_array_equal(np.diff(stamps), 5_000_000)
