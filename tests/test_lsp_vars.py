"""The language server and run-time values, driven by a real LSP client over stdio:
completion of vars and kinds, hover, references across a behaviour and the top level,
rename (done and refused), semantic tokens, outline."""

import re
import sys
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pygls.exceptions import JsonRpcException
from pytest_lsp import ClientServerConfig, LanguageClient

from robocop_dsl.lsp.semantic_tokens import TOKEN_TYPES

REPO = Path(__file__).resolve().parent.parent
FOLDER = REPO / "tests" / "fixtures" / "lsp"
MISSION = FOLDER / "counting.mission"
LINES = MISSION.read_text().splitlines()


@pytest_lsp.fixture(config=ClientServerConfig(
    server_command=[sys.executable, "-m", "robocop_dsl", "lsp"]))
async def client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(types.InitializeParams(
        capabilities=types.ClientCapabilities(),
        workspace_folders=[types.WorkspaceFolder(FOLDER.as_uri(), "lsp")]))
    yield
    await lsp_client.shutdown_session()


async def open_document(client: LanguageClient, text: str | None = None) -> str:
    """Open the mission (with ``text`` instead of its own) and wait for its
    diagnostics."""
    uri = MISSION.as_uri()
    client.text_document_did_open(types.DidOpenTextDocumentParams(types.TextDocumentItem(
        uri, "mission", 1, MISSION.read_text() if text is None else text)))
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    return uri


def line_of(text: str) -> int:
    """The 1-based line of the mission that holds ``text``."""
    return next(n for n, line in enumerate(LINES, 1) if text in line)


def at(line: int, word: str, nth: int = 0) -> types.Position:
    """The position of the ``nth`` whole ``word`` on 1-based ``line``."""
    found = [m.start() for m in re.finditer(rf"\b{word}\b", LINES[line - 1])]
    return types.Position(line - 1, found[nth])


def written(edit: types.TextEdit) -> str:
    """The text an edit of the mission replaces."""
    start, end = edit.range.start, edit.range.end
    assert start.line == end.line
    return LINES[start.line][start.character:end.character]


async def complete(client: LanguageClient, uri: str, line: int, character: int) -> set:
    found = await client.text_document_completion_async(types.CompletionParams(
        types.TextDocumentIdentifier(uri), types.Position(line - 1, character)))
    return {item.label for item in found.items}


@pytest.mark.asyncio
async def test_completion_of_vars_and_kinds(client: LanguageClient):
    """After ``NAME =`` in a behaviour's action the vars it sees are offered (its own
    and the mission's, not a region's elsewhere); in a log text's ``{`` too; after
    ``var NAME:`` the kinds."""
    number = line_of("started = time")
    typed = "            started = started + "
    text = LINES[:number - 1] + [typed] + LINES[number:]
    text[line_of("var deadline") - 1] = "var deadline: "
    uri = await open_document(client, "\n".join(text) + "\n")
    labels = await complete(client, uri, number, len(typed))
    assert {"started", "touches", "reach_time", "hover_height", "time", "force"} <= labels
    assert "lifted" not in labels and "elapsed" not in labels
    kinds = await complete(client, uri, line_of("var deadline"), len("var deadline: "))
    assert {"count", "length", "force", "position"} <= kinds

    placeholder = LINES[line_of('"touches: {') - 1].index("{touches}") + 1
    labels = await complete(client, uri, line_of('"touches: {'), placeholder)
    assert {"touches", "touch_z", "touch_limit"} <= labels and "started" not in labels


@pytest.mark.asyncio
async def test_hover_shows_the_kind_and_the_place(client: LanguageClient):
    """Hover on a var's use shows its declaration, first value and scope; on a
    behaviour's var that it is one per instance; on a kind what it holds."""
    uri = await open_document(client)

    async def hover(position):
        found = await client.text_document_hover_async(types.HoverParams(
            types.TextDocumentIdentifier(uri), position))
        return found.contents.value

    touches = await hover(at(line_of("touches = touches + 1"), "touches", 1))
    assert "var touches: count = 0" in touches
    assert "a whole number" in touches and f"counting.mission:{line_of('var touches')}" in touches
    started = await hover(at(line_of("reach_time = time - started"), "started"))
    assert "var started: duration = 0 s" in started and "one per instance" in started
    assert "behavior `hover`" in started
    assert "a length (m)" in await hover(at(line_of("var touch_z"), "length"))


@pytest.mark.asyncio
async def test_references_across_a_behaviour_and_the_top_level(client: LanguageClient):
    """A top var's references: its declaration, its assignment and log text inside the
    behaviour, the log text of the state that instantiates it; definition from a log
    text leads to the declaration."""
    uri = await open_document(client)
    use = at(line_of("reach_time = time"), "reach_time")
    found = await client.text_document_references_async(types.ReferenceParams(
        text_document=types.TextDocumentIdentifier(uri), position=use,
        context=types.ReferenceContext(include_declaration=True)))
    places = sorted((r.range.start.line + 1, r.range.start.character) for r in found)
    expected = [(n, m.start()) for n, line in enumerate(LINES, 1)
                for m in re.finditer(r"\breach_time\b", line)]
    assert places == expected and len(places) == 4
    assert {line_of("var reach_time"), line_of('"approached in')} <= {n for n, _ in places}

    placeholder = at(line_of('"approached in'), "reach_time")
    definition = await client.text_document_definition_async(types.DefinitionParams(
        types.TextDocumentIdentifier(uri), placeholder))
    assert definition[0].range.start.line == line_of("var reach_time") - 1


@pytest.mark.asyncio
async def test_rename_a_var(client: LanguageClient):
    """Renaming a var edits its declaration, every assignment, read and log text."""
    uri = await open_document(client)
    edit = await client.text_document_rename_async(types.RenameParams(
        types.TextDocumentIdentifier(uri), at(line_of("var touches"), "touches"), "visits_done"))
    edits = edit.changes[uri]
    assert {written(e) for e in edits} == {"touches"}
    lines = {e.range.start.line + 1 for e in edits}
    assert lines == {line_of("var touches"), line_of("touches = touches"),
                     line_of('"touches: {touches}'), line_of("touches < touch_limit")}
    assert len(edits) == 5


@pytest.mark.asyncio
@pytest.mark.parametrize("line, name, new_name, reason", [
    ("var touches", "touches", "hand", "already the task"),
    ("var touches", "touches", "touch_limit", "already the constant"),
    ("var touches", "touches", "lifted", "already the var"),
    ("var started", "started", "tool", "already the parameter"),
    ("var lifted", "lifted", "rising", "already the state"),
    ("var touches", "touches", "2nd", "is not a name"),
    ("var touches", "touches", "force", "is not a name"),
])
async def test_rename_refused(client: LanguageClient, line, name, new_name, reason):
    """A new name already taken where the var is seen, or no name, is refused with an
    error that says why."""
    uri = await open_document(client)
    with pytest.raises(JsonRpcException, match=reason):
        await client.text_document_rename_async(types.RenameParams(
            types.TextDocumentIdentifier(uri), at(line_of(line), name), new_name))


@pytest.mark.asyncio
async def test_semantic_tokens_of_a_var(client: LanguageClient):
    """A var has one token type where it is declared and where it is used; so has a
    constant."""
    uri = await open_document(client)
    tokens = await client.text_document_semantic_tokens_full_async(
        types.SemanticTokensParams(types.TextDocumentIdentifier(uri)))
    types_by_word: dict[str, set] = {}
    line = start = 0
    data = tokens.data
    for index in range(0, len(data), 5):
        delta_line, delta_start, length, kind, _ = data[index:index + 5]
        line, start = line + delta_line, (start if not delta_line else 0) + delta_start
        word = LINES[line][start:start + length]
        types_by_word.setdefault(word, set()).add(TOKEN_TYPES[kind])
    assert types_by_word["touches"] == types_by_word["started"] == {"variable"}
    assert types_by_word["lifted"] == types_by_word["reach_time"] == {"variable"}
    assert types_by_word["hover_height"] == {"macro"}


@pytest.mark.asyncio
async def test_outline_lists_vars(client: LanguageClient):
    """The outline shows each var with its kind, inside the behaviour or region that
    declares it."""
    uri = await open_document(client)
    symbols = await client.text_document_document_symbol_async(
        types.DocumentSymbolParams(types.TextDocumentIdentifier(uri)))
    top = {s.name: s for s in symbols}
    assert top["touches"].detail == "var: count"
    assert top["hover"].children[0].name == "started"
    lift = top["up"].children[0]
    assert (lift.name, lift.children[0].name, lift.children[0].detail) == \
        ("lift", "lifted", "var: length")
