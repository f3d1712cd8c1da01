"""The editor's process watched: the protocol asks a server to exit once the process
that started it is gone (``processId`` at initialization, ``--clientProcessId`` on the
command line), so that a crashed editor leaves no server behind."""

from __future__ import annotations

import os
import threading
import time

POLL = 1.0
"""Seconds between two looks at the editor's process."""


def alive(pid: int) -> bool:
    """Whether process ``pid`` exists (POSIX; elsewhere, taken to be alive)."""
    if os.name != "posix":
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:         # another user's process: it exists
        return True
    return True


def watch(pid: int | None) -> None:
    """End this process (exit code 1) within :data:`POLL` of process ``pid`` ending."""
    if not pid or pid == os.getpid():
        return

    def look():
        while alive(pid):
            time.sleep(POLL)
        os._exit(1)

    threading.Thread(target=look, name="editor watch", daemon=True).start()
