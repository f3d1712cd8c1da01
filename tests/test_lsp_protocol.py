"""The language server speaks the protocol as a client negotiates it, driven over
stdio: positions in UTF-8 and UTF-16 on a line with accented and astral characters,
quick fixes that leave a clean document, references into the world, rename refusals,
error replies to requests outside their document, and an exit at once."""

import asyncio
import sys
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pygls.exceptions import JsonRpcInvalidParams
from pytest_lsp import ClientServerConfig, LanguageClient, make_test_lsp_client

REPO = Path(__file__).resolve().parent.parent
MISSIONS = REPO / "missions"
ACCENTED = '''mission accents "é and 🤖"

world "bazar/sophia.yaml"

var count: count = 0

state s {
    enter { log "café 🤖 {coutn} then {count}" }
    when elapsed > 1 s -> done { count = count + 1 }
}

final done
'''
LOG_LINE = 7
CODECS = {types.PositionEncodingKind.Utf8: "utf-8",
          types.PositionEncodingKind.Utf16: "utf-16-le"}


@pytest_lsp.fixture(
    params=[types.PositionEncodingKind.Utf8, types.PositionEncodingKind.Utf16],
    config=ClientServerConfig(server_command=[sys.executable, "-m", "robocop_dsl", "lsp"]))
async def client(lsp_client: LanguageClient, request):
    lsp_client.encoding = request.param
    lsp_client.initialized_with = await lsp_client.initialize_session(types.InitializeParams(
        capabilities=types.ClientCapabilities(general=types.GeneralClientCapabilities(
            position_encodings=[request.param])),
        workspace_folders=[types.WorkspaceFolder(MISSIONS.as_uri(), "missions")]))
    yield
    await lsp_client.shutdown_session()


def width(encoding: str) -> int:
    """Bytes per code unit."""
    return 2 if encoding == types.PositionEncodingKind.Utf16 else 1


def units(client: LanguageClient, text: str) -> int:
    """The length of ``text`` in the code units of the encoding negotiated."""
    return len(text.encode(CODECS[client.encoding])) // width(client.encoding)


def written(client: LanguageClient, line: str, range_: types.Range) -> str:
    """The part of ``line`` that a range on it covers, read in the negotiated units."""
    data, size = line.encode(CODECS[client.encoding]), width(client.encoding)
    return data[range_.start.character * size:range_.end.character * size].decode(
        CODECS[client.encoding])


async def opened(client: LanguageClient, path: Path, text: str | None = None) -> str:
    uri = path.as_uri()
    client.text_document_did_open(types.DidOpenTextDocumentParams(types.TextDocumentItem(
        uri, "mission", 1, path.read_text() if text is None else text)))
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    return uri


async def changed(client: LanguageClient, uri: str, version: int, text: str) -> list:
    """Send the whole new text and wait for the diagnostics of that version."""
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        types.VersionedTextDocumentIdentifier(version=version, uri=uri),
        [types.TextDocumentContentChangeWholeDocument(text)]))
    while True:
        published = await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        if published.uri == uri and published.version == version:
            return published.diagnostics


@pytest.mark.asyncio
async def test_positions_in_the_negotiated_encoding(client: LanguageClient, tmp_path):
    """On a line with 'é' and '🤖', the diagnostic's range, a completion's edit range
    and a rename's edit ranges are counted in the negotiated code units."""
    assert client.initialized_with.capabilities.position_encoding == client.encoding
    path = tmp_path / "accents.mission"
    path.write_text(ACCENTED, encoding="utf-8")
    uri = await opened(client, path)
    line = ACCENTED.splitlines()[LOG_LINE]
    unknown = next(d for d in client.diagnostics[uri] if d.code == "unknown-name")
    assert unknown.range.start.line == LOG_LINE
    assert written(client, line, unknown.range) == "{coutn}"

    cursor = line.index("{count}") + len("{co")
    found = await client.text_document_completion_async(types.CompletionParams(
        types.TextDocumentIdentifier(uri), types.Position(LOG_LINE, units(client, line[:cursor]))))
    item = next(i for i in found.items if i.label == "count")
    assert written(client, line, item.text_edit.range) == "co"

    declaration = ACCENTED.splitlines()[4]
    edit = await client.text_document_rename_async(types.RenameParams(
        types.TextDocumentIdentifier(uri),
        types.Position(4, units(client, declaration[:declaration.index("count")])), "total"))
    on_line = [e for e in edit.changes[uri] if e.range.start.line == LOG_LINE]
    assert [written(client, line, e.range) for e in on_line] == ["count"]


def applied(text: str, edits: list[types.TextEdit], encoding: str) -> str:
    """``text`` with ``edits`` (ranges in ``encoding``'s units) applied, last first."""
    lines = text.split("\n")
    codec, size = CODECS[encoding], width(encoding)
    for edit in sorted(edits, key=lambda e: (e.range.start.line, e.range.start.character),
                       reverse=True):
        start, end = edit.range.start, edit.range.end
        head = lines[start.line].encode(codec)[:start.character * size].decode(codec)
        tail = lines[end.line].encode(codec)[end.character * size:].decode(codec)
        lines[start.line:end.line + 1] = (head + edit.new_text + tail).split("\n")
    return "\n".join(lines)


async def fix_all(client: LanguageClient, uri: str, text: str) -> str:
    """``text`` with the preferred quick fix of each of its diagnostics applied."""
    edits = []
    for diagnostic in client.diagnostics[uri]:
        actions = await client.text_document_code_action_async(types.CodeActionParams(
            types.TextDocumentIdentifier(uri), diagnostic.range,
            types.CodeActionContext([diagnostic])))
        preferred = next(a for a in actions if a.is_preferred)
        assert preferred.kind == types.CodeActionKind.QuickFix
        edits += preferred.edit.changes[uri]
    return applied(text, edits, client.encoding)


CLEAN = ACCENTED.replace("coutn", "count")


@pytest.mark.asyncio
@pytest.mark.parametrize("broken", [
    ACCENTED,
    ACCENTED.replace("-> done {", "done {"),
    ACCENTED.replace("var count: count = 0", "var count: count: 0"),
    CLEAN.replace("count + 1 }\n}\n", "count + 1 }\n"),
    CLEAN.replace("state s {", "stat s {"),
], ids=["did-you-mean", "missing arrow", "colon for equals", "unclosed block", "misspelt keyword"])
async def test_quick_fixes_leave_a_clean_document(client: LanguageClient, tmp_path, broken):
    """A did-you-mean hint's replacement (of a name, of a misspelt keyword), a missing
    '->', a ':' written for '=' and a block left open are mended by their quick fixes:
    the document then checks clean."""
    path = tmp_path / "fixable.mission"
    path.write_text(broken, encoding="utf-8")
    uri = await opened(client, path)
    text, version = broken, 1
    while client.diagnostics[uri] and version < 4:
        text = await fix_all(client, uri, text)
        version += 1
        await changed(client, uri, version, text)
    assert list(client.diagnostics[uri]) == []
    assert text == CLEAN


def raw_position(line: int, character: int) -> types.Position:
    """A position the protocol's types would refuse to build (out of range)."""
    position = types.Position(0, 0)
    object.__setattr__(position, "line", line)
    object.__setattr__(position, "character", character)
    return position


@pytest.mark.asyncio
@pytest.mark.parametrize("line, character, reason", [
    (-1, 0, "Position.line should be in range"),
    (0, 2 ** 31, "Position.character should be in range"),
    (40, 0, "line 40 is past the end of pickup.mission"),
])
async def test_a_position_outside_the_document_gets_an_error(client: LanguageClient, line,
                                                             character, reason):
    """A negative position, one past 2^31 - 1 or a line past the end is answered with
    an 'invalid params' error saying so, for every request that takes a position."""
    uri = await opened(client, MISSIONS / "pickup.mission", "mission m\n" * 10)
    document = types.TextDocumentIdentifier(uri)
    at = raw_position(line, character)
    requests = [
        client.text_document_hover_async(types.HoverParams(document, at)),
        client.text_document_completion_async(types.CompletionParams(document, at)),
        client.text_document_definition_async(types.DefinitionParams(document, at)),
        client.text_document_rename_async(types.RenameParams(document, at, "x")),
        client.text_document_signature_help_async(types.SignatureHelpParams(document, at)),
    ]
    for request in requests:
        with pytest.raises(JsonRpcInvalidParams, match=reason):
            await request


@pytest.mark.asyncio
async def test_an_unknown_document_gets_an_error(client: LanguageClient, tmp_path):
    """A request about a document that is neither open nor on disk is refused."""
    document = types.TextDocumentIdentifier((tmp_path / "nowhere.mission").as_uri())
    with pytest.raises(JsonRpcInvalidParams, match="unknown document"):
        await client.text_document_hover_async(
            types.HoverParams(document, types.Position(0, 0)))
    with pytest.raises(JsonRpcInvalidParams, match="unknown document"):
        await client.text_document_semantic_tokens_full_async(
            types.SemanticTokensParams(document))


@pytest.mark.asyncio
async def test_exit_ends_the_process_at_once(tmp_path):
    """After ``shutdown``, ``exit`` ends the server with code 0 even while it is
    checking a large mission (waited for up to a generous bound: the bench measures
    the time)."""
    client = make_test_lsp_client()
    await client.start_io(sys.executable, "-m", "robocop_dsl", "lsp", "--stdio")
    await client.initialize_session(types.InitializeParams(capabilities=types.ClientCapabilities()))
    pickup = (MISSIONS / "pickup.mission").read_text()
    large = pickup + "".join(pickup.split("start goto_initial_pose")[1].replace(
        "state ", f"state copy{i}_").split("when controller")[0] for i in range(40))
    path = tmp_path / "large.mission"
    client.text_document_did_open(types.DidOpenTextDocumentParams(
        types.TextDocumentItem(path.as_uri(), "mission", 1, large)))
    await client.shutdown_async(None)
    client.exit(None)
    await asyncio.wait_for(client._server.wait(), timeout=30)
    assert client._server.returncode == 0
    await client.stop()


@pytest.mark.asyncio
async def test_a_misspelt_behaviour_argument_is_fixed_where_it_is_written(
        client: LanguageClient, tmp_path):
    """The error is reported inside the behaviour, where the argument is used; its
    quick fix edits the argument of the instance (named by the diagnostic's note)."""
    clean = (MISSIONS / "pickup.mission").read_text().replace(
        '"bazar/sophia.yaml"', f'"{REPO / "robots/bazar/sophia.yaml"}"')
    broken = clean.replace("state grasp: reach(pickup_point,", "state grasp: reach(pickup_pont,")
    path = tmp_path / "typo.mission"
    path.write_text(broken)
    uri = await opened(client, path)
    [diagnostic] = client.diagnostics[uri]
    assert diagnostic.code == "unknown-body"
    fixed = await fix_all(client, uri, broken)
    assert fixed == clean
    assert not await changed(client, uri, 2, fixed)
