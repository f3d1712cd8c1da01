"""Open documents as a real client keeps them: a document that is no file (VS Code's
``untitled:`` scheme) is served like any other and has no folder; a change whose range
ends before it starts replaces the text between its two ends."""

import os
import sys
from pathlib import Path

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient, make_test_lsp_client

REPO = Path(__file__).resolve().parent.parent
MISSIONS = REPO / "missions"
SERVER = [sys.executable, "-m", "robocop_dsl", "lsp", "--stdio"]
UNTITLED = "untitled:Untitled-1"
TWO_STATES = '''mission m

world "bazar/sophia.yaml"

state s {
    when elapsed > 1 s -> doXYZne
    when elapsed > 2 s -> t
}

state t {
    when elapsed > 1 s -> done
}

final done
'''


async def started(folder: Path) -> LanguageClient:
    """A client of a server whose working folder is ``folder``."""
    client = make_test_lsp_client()
    paths = os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))
    await client.start_io(*SERVER, cwd=folder, env={**os.environ, "PYTHONPATH": paths})
    await client.initialize_session(types.InitializeParams(
        capabilities=types.ClientCapabilities()))
    return client


async def published(client: LanguageClient, uri: str, version: int):
    """The diagnostics of version ``version`` of ``uri``."""
    while True:
        found = await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        if found.uri == uri and found.version == version:
            return found.diagnostics


def opened(client: LanguageClient, uri: str, text: str) -> None:
    client.text_document_did_open(types.DidOpenTextDocumentParams(
        types.TextDocumentItem(uri, "mission", 1, text)))


def changed(client: LanguageClient, uri: str, version: int, start: tuple[int, int],
            end: tuple[int, int], text: str = "") -> None:
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        types.VersionedTextDocumentIdentifier(version=version, uri=uri),
        [types.TextDocumentContentChangePartial(
            types.Range(types.Position(*start), types.Position(*end)), text)]))


@pytest.mark.asyncio
async def test_an_unsaved_document_is_served_and_has_no_folder():
    """Completion, hover and quick fixes answer on an ``untitled:`` document as on a
    file; its relative import is not found, though a file of that name is in the
    server's working folder, and its world is found along the robots path."""
    client = await started(MISSIONS)
    text = (MISSIONS / "two_parts.mission").read_text().replace("-> failed", "-> faild", 1)
    opened(client, UNTITLED, text)
    diagnostics = await published(client, UNTITLED, 1)
    missing = [d for d in diagnostics if d.code == "import-not-found"]
    assert missing and "bazar_common.mission" in missing[0].message
    assert not any(d.code == "world-not-found" for d in diagnostics)
    document = types.TextDocumentIdentifier(UNTITLED)
    lines = text.splitlines()
    body = types.Position(5, lines[5].index("bazar_left") + 3)
    hover = await client.text_document_hover_async(types.HoverParams(document, body))
    assert "parent" in hover.contents.value
    when = types.Position(9, lines[9].index("home.there"))
    completion = await client.text_document_completion_async(
        types.CompletionParams(document, when))
    assert "home" in [item.label for item in completion.items]
    typo = next(d for d in diagnostics if d.code == "unknown-state")
    [fix] = await client.text_document_code_action_async(types.CodeActionParams(
        document, typo.range, types.CodeActionContext([typo])))
    assert fix.edit.changes[UNTITLED][0].new_text == "failed"
    await client.shutdown_session()


@pytest.mark.asyncio
async def test_a_change_whose_range_ends_before_it_starts_replaces_the_text_between(
        tmp_path):
    """A reversed range (on one line, then over lines) is the text between its ends,
    as editors read it: nothing is duplicated, and the log says what was done."""
    client = await started(REPO)
    uri = (tmp_path / "m.mission").as_uri()
    opened(client, uri, TWO_STATES)
    assert [d.code for d in await published(client, uri, 1)] == ["unknown-state"]
    typo = TWO_STATES.splitlines()[5].index("XYZ")
    changed(client, uri, 2, (5, typo + 3), (5, typo))
    assert not await published(client, uri, 2)
    changed(client, uri, 3, (13, 0), (9, 0))
    assert [d.code for d in await published(client, uri, 3)] == ["unknown-state"]
    outline = await client.text_document_document_symbol_async(
        types.DocumentSymbolParams(types.TextDocumentIdentifier(uri)))
    assert [symbol.name for symbol in outline] == ["s", "done"]
    warned = [m.message for m in client.log_messages
              if m.type == types.MessageType.Warning]
    assert len(warned) == 2
    assert f"ends (5:{typo}) before it starts (5:{typo + 3})" in warned[0]
    await client.shutdown_session()
