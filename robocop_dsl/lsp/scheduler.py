"""When open documents are checked. An edit restarts a short wait (:data:`DELAY`) and
only the text of the last edit is checked: a thousand edits in a row make one check.
Checks run one at a time on their own thread, in the order they fell due; one whose
document changed meanwhile stops at its next stage and publishes nothing. Diagnostics
carry the version of the text they are for. After an edited document's check, the open
documents that import it are checked again."""

from __future__ import annotations

import asyncio
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Callable

DELAY = 0.2
"""The quiet time after an edit before its document is checked [s]."""


class Checks:
    """The checks of open documents, whose texts are ``texts``. On the checking thread,
    ``run(path, text, stale)`` checks ``text`` as the content of ``path`` and gives what
    to publish (``None`` when ``stale()`` turned true) and ``importers(path)`` gives the
    open documents that import ``path``. On the event loop's thread, where every method
    of this class runs, ``publish(path, found, version)`` sends what a check found and
    ``failed(path, error)`` says that a check raised."""

    def __init__(self, texts: dict[Path, str], run: Callable, publish: Callable,
                 importers: Callable[[Path], list[Path]], failed: Callable):
        self.texts, self.run, self.importers = texts, run, importers
        self.publish, self.failed = publish, failed
        self.versions: dict[Path, int | None] = {}
        self._worker = ThreadPoolExecutor(max_workers=1, thread_name_prefix="check")
        self._timers: dict[Path, asyncio.TimerHandle] = {}
        self._edited: dict[Path, bool] = {}
        self._due: dict[Path, bool] = {}
        self._running = False
        self._stopped = False

    def request(self, path: Path, delay: float = DELAY, edited: bool = True) -> None:
        """Check ``path`` once nothing asked for it again for ``delay`` seconds;
        ``edited`` when its own text changed (its importers are checked after it)."""
        timer = self._timers.pop(path, None)
        if timer is not None:
            timer.cancel()
            edited = edited or self._edited.get(path, False)
        self._edited[path] = edited
        self._timers[path] = asyncio.get_running_loop().call_later(delay, self._fall_due, path)

    def stop(self) -> None:
        """Check nothing more (the server is shutting down)."""
        self._stopped = True
        for timer in self._timers.values():
            timer.cancel()
        self._timers.clear()

    def _fall_due(self, path: Path) -> None:
        self._timers.pop(path, None)
        edited = self._edited.pop(path, False)
        self._due[path] = self._due.get(path, False) or edited
        self._start_next()

    def _start_next(self) -> None:
        while self._due and not self._running and not self._stopped:
            path = next(iter(self._due))
            edited = self._due.pop(path)
            text = self.texts.get(path)
            if text is None:
                continue
            self._running = True
            version = self.versions.get(path)
            future = asyncio.get_running_loop().run_in_executor(
                self._worker, self._check, path, text, edited)
            future.add_done_callback(lambda done: self._finished(path, text, version, done))

    def _check(self, path: Path, text: str, edited: bool):
        """On the checking thread: what to publish and the documents to check next."""
        found = self.run(path, text, lambda: self.texts.get(path) is not text)
        if found is None:
            return None
        return found, self.importers(path) if edited else []

    def _finished(self, path: Path, text: str, version: int | None,
                  done: asyncio.Future) -> None:
        self._running = False
        error = done.exception()
        if error is not None:
            self.failed(path, error)
        elif done.result() is not None and self.texts.get(path) is text and not self._stopped:
            found, importers = done.result()
            self.publish(path, found, version)
            for other in importers:
                self.request(other, 0, edited=False)
        self._start_next()
