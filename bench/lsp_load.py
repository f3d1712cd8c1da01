"""The language server under load, driven as an editor drives it (stdio, one server
process per measure).

- open a large mission (``--size`` bytes, 5 MB by default: the states of
  missions/pickup.mission repeated, renamed and chained): the time from ``didOpen`` to
  its diagnostics, the semantic tokens' time after them, and the server's peak resident
  memory (sampled every 20 ms from the open to the tokens); beside them, in this
  process, the CPU time of lark's LALR parser alone on the same text (the mission
  grammar and its line-break post-lexer, lark's own tree without positions, not the
  project's syntax tree): the floor under the server's parse;
- ``--edits`` one-character edits of missions/pickup.mission (a comment typed at its
  end), sent back to back: the time from the last edit to the diagnostics of its
  version, and how many times diagnostics were published in all;
- ``shutdown`` then ``exit``: the time from ``exit`` to the end of the process.

Prints a table of each figure beside its target.

    python bench/lsp_load.py [--size 5000000] [--edits 1000]
"""

from __future__ import annotations

import argparse
import asyncio
import re
import sys
import tempfile
import time
from pathlib import Path

import psutil
from lsprotocol import types
from pytest_lsp import LanguageClient
from pytest_lsp.client import DEFAULT_CLIENT_FEATURES, register_lsp_features

from robocop_dsl.lang.parser import GRAMMAR_DIR, StatementBreaks

REPO = Path(__file__).resolve().parent.parent
PICKUP = REPO / "missions" / "pickup.mission"
_STATES = ("goto_initial_pose", "approach", "grasp", "lift", "move_to_drop", "release",
           "return")


def large_mission(size: int) -> str:
    """pickup.mission with its states repeated (renamed ``NAME_K``, each copy's last
    state leading to the next copy) until the text is ``size`` characters long."""
    lines = PICKUP.read_text(encoding="utf-8").split("\n")
    start = next(i for i, line in enumerate(lines) if line.startswith("start "))
    guard = next(i for i, line in enumerate(lines) if line.startswith("when controller"))
    head = "\n".join(lines[:start]).replace('"bazar/', f'"{REPO}/robots/bazar/')
    states, tail = "\n".join(lines[start + 2:guard]), "\n".join(lines[guard:])
    parts, length, copy = [head, "\nstart goto_initial_pose_0\n"], len(head), 0
    while length < size:
        block = re.sub(rf"\b({'|'.join(_STATES)})\b", rf"\1_{copy}", states)
        block = block.replace("-> done", f"-> goto_initial_pose_{copy + 1}") + "\n"
        parts.append(block)
        length += len(block)
        copy += 1
    parts.append(f"state goto_initial_pose_{copy} {{\n    when elapsed > 1 s -> done\n}}\n\n")
    return "".join(parts) + tail


async def started():
    """A server process and a client that keeps the version of every diagnostics
    published (``client.published``)."""
    client = LanguageClient()
    client.published = []
    register_lsp_features(client, {k: f for k, f in DEFAULT_CLIENT_FEATURES.items()
                                   if k != types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS})

    @client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def published(params: types.PublishDiagnosticsParams):
        client.diagnostics[params.uri] = params.diagnostics
        client.published.append(params.version)

    await client.start_io(sys.executable, "-m", "robocop_dsl", "lsp", "--stdio")
    await client.initialize_session(types.InitializeParams(
        capabilities=types.ClientCapabilities()))
    return client, psutil.Process(client._server.pid)


async def sample_peak(process: psutil.Process, peak: list[int]) -> None:
    """Keep ``peak[0]`` at the largest resident set size seen [bytes]."""
    while True:
        try:
            peak[0] = max(peak[0], process.memory_info().rss)
        except psutil.NoSuchProcess:
            return
        await asyncio.sleep(0.02)


async def open_large(size: int) -> dict:
    """Open a mission of ``size`` characters: seconds to diagnostics and to semantic
    tokens, peak memory [MB]."""
    client, process = await started()
    peak = [0]
    sampler = asyncio.create_task(sample_peak(process, peak))
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "large.mission"
        text = large_mission(size)
        path.write_text(text, encoding="utf-8")
        uri = path.as_uri()
        start = time.perf_counter()
        client.text_document_did_open(types.DidOpenTextDocumentParams(
            types.TextDocumentItem(uri, "mission", 1, text)))
        await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        checked = time.perf_counter() - start
        start = time.perf_counter()
        await client.text_document_semantic_tokens_full_async(
            types.SemanticTokensParams(types.TextDocumentIdentifier(uri)))
        tokens = time.perf_counter() - start
        errors = sum(1 for d in client.diagnostics[uri] if d.severity == 1)
    sampler.cancel()
    await client.shutdown_session()
    return {"length": len(text), "diagnostics": checked, "tokens": tokens,
            "peak": peak[0] / 2 ** 20, "errors": errors}


def lark_alone(text: str) -> float:
    """CPU seconds of lark's LALR parser on ``text``: lark's own tree, without positions
    (the project's syntax tree is not built)."""
    from lark import Lark

    parser = Lark((GRAMMAR_DIR / "mission.lark").read_text(encoding="utf-8"), parser="lalr",
                  lexer="contextual", postlex=StatementBreaks(), import_paths=[GRAMMAR_DIR])
    start = time.process_time()
    parser.parse(text)
    return time.process_time() - start


async def edit_in_a_row(edits: int) -> dict:
    """``edits`` one-character edits of pickup.mission sent back to back: seconds from
    the last to its diagnostics, and how many diagnostics were published."""
    client, _ = await started()
    uri, text = PICKUP.as_uri(), PICKUP.read_text(encoding="utf-8")
    client.text_document_did_open(types.DidOpenTextDocumentParams(
        types.TextDocumentItem(uri, "mission", 1, text)))
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    published = client.published
    published.clear()
    line = len(text.split("\n")) - 1
    typed = "# " + "edited " * (edits // 7 + 1)
    for version, character in enumerate(typed[:edits], 2):
        at = types.Position(line, version - 2)
        client.text_document_did_change(types.DidChangeTextDocumentParams(
            types.VersionedTextDocumentIdentifier(version=version, uri=uri),
            [types.TextDocumentContentChangePartial(types.Range(at, at), character)]))
    last = edits + 1
    start = time.perf_counter()
    while edits and last not in published:
        await asyncio.sleep(0.005)
    after = time.perf_counter() - start
    exit_time = await exit_time_of(client)
    return {"after": after, "published": len(published), "exit": exit_time}


async def exit_time_of(client) -> float:
    """``shutdown``, then seconds from ``exit`` to the end of the server process."""
    await client.shutdown_async(None)
    start = time.perf_counter()
    client.exit(None)
    await client._server.wait()
    elapsed = time.perf_counter() - start
    await client.stop()
    return elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=5_000_000)
    parser.add_argument("--edits", type=int, default=1000)
    args = parser.parse_args()
    large = asyncio.run(open_large(args.size))
    edited = asyncio.run(edit_in_a_row(args.edits))
    rows = [
        (f"open a {large['length'] / 1e6:.1f} MB mission: diagnostics", "s",
         large["diagnostics"], "10"),
        ("  then its semantic tokens", "s", large["tokens"], ""),
        ("  lark's parser alone on its text (CPU)", "s", lark_alone(large_mission(args.size)),
         ""),
        ("  server's peak resident memory", "MB", large["peak"], "500"),
        (f"{args.edits} edits in a row: last edit -> its diagnostics", "s", edited["after"],
         "2"),
        ("  diagnostics published in all", "", edited["published"], ""),
        ("exit -> process ended", "s", edited["exit"], "1"),
    ]
    print(f"{'measure':58}{'unit':>6}{'value':>10}{'target':>8}")
    for label, unit, value, target in rows:
        shown = f"{value:.2f}" if isinstance(value, float) else str(value)
        print(f"{label:58}{unit:>6}{shown:>10}{target:>8}")


if __name__ == "__main__":
    main()
