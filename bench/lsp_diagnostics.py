"""Time from an edit to its diagnostics in the language server, on a mission.

Starts ``robocop-mission lsp`` as an editor does (stdio), opens the mission (the world
loads), then sends ``--edits`` whole-text changes, alternately adding and removing a
comment line, and times each from sending the change to receiving its
``publishDiagnostics``. For comparison, the same process times an in-process
``check_source`` of the text with the world already loaded. Prints a table of the
median, 95th percentile and maximum in milliseconds, and the ratio of the server's
median to the in-process check's.

    python bench/lsp_diagnostics.py [--edits 50] [MISSION]
"""

from __future__ import annotations

import argparse
import asyncio
import statistics
import sys
import time
from pathlib import Path

from lsprotocol import types
from pytest_lsp import make_test_lsp_client

from robocop_dsl.compile import WorldCache, check_source

REPO = Path(__file__).resolve().parent.parent


def percentile(values: list[float], fraction: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(fraction * len(ordered)))]


async def server_times(path: Path, edits: int) -> tuple[float, list[float]]:
    """The open's and each edit's time to diagnostics [s]."""
    client = make_test_lsp_client()
    await client.start_io(sys.executable, "-m", "robocop_dsl", "lsp")
    await client.initialize_session(types.InitializeParams(capabilities=types.ClientCapabilities()))
    uri, text = path.resolve().as_uri(), path.read_text(encoding="utf-8")
    start = time.perf_counter()
    client.text_document_did_open(types.DidOpenTextDocumentParams(
        types.TextDocumentItem(uri, "mission", 1, text)))
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    opened = time.perf_counter() - start
    times = []
    for version in range(2, edits + 2):
        edited = text + ("# edited\n" if version % 2 else "")
        waiting = client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        start = time.perf_counter()
        client.text_document_did_change(types.DidChangeTextDocumentParams(
            types.VersionedTextDocumentIdentifier(version=version, uri=uri),
            [types.TextDocumentContentChangeWholeDocument(edited)]))
        await waiting
        times.append(time.perf_counter() - start)
    await client.shutdown_session()
    return opened, times


def check_times(path: Path, runs: int) -> list[float]:
    """In-process checks of the text with the world loaded [s]."""
    cache, text = WorldCache(), path.read_text(encoding="utf-8")
    check_source(text, str(path), cache=cache)
    times = []
    for index in range(runs):
        start = time.perf_counter()
        check_source(text + ("# edited\n" if index % 2 else ""), str(path), cache=cache)
        times.append(time.perf_counter() - start)
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mission", nargs="?", default=str(REPO / "missions" / "pickup.mission"))
    parser.add_argument("--edits", type=int, default=50)
    args = parser.parse_args()
    path = Path(args.mission)
    opened, served = asyncio.run(server_times(path, args.edits))
    checked = check_times(path, args.edits)
    print(f"{path.name}: {args.edits} edits; open with world load {opened * 1e3:.0f} ms")
    print(f"{'':34}{'median':>8}{'p95':>8}{'max':>8}")
    for label, values in (("edit -> diagnostics (server)", served),
                          ("check_source in process", checked)):
        print(f"{label:34}{statistics.median(values) * 1e3:8.1f}"
              f"{percentile(values, 0.95) * 1e3:8.1f}{max(values) * 1e3:8.1f}")
    print(f"ratio server / in-process median: "
          f"{statistics.median(served) / statistics.median(checked):.2f}")


if __name__ == "__main__":
    main()
