"""The language server and run-time values, driven by a real LSP client over stdio:
completion of vars and kinds, hover, references across a behaviour and the top level,
rename (done and refused), semantic tokens, outline, the bodies of force, torque and
contact; and every position of missions with vars answered, as written and half typed."""

import re
import sys
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pygls.exceptions import JsonRpcException, JsonRpcInvalidParams
from pytest_lsp import ClientServerConfig, LanguageClient

from robocop_dsl.lsp import completion, hover, navigation, semantic_tokens, symbols
from robocop_dsl.lsp.project import Project
from robocop_dsl.lsp.semantic_tokens import TOKEN_TYPES

REPO = Path(__file__).resolve().parent.parent
FOLDER = REPO / "tests" / "fixtures" / "lsp"
MISSION = FOLDER / "counting.mission"
PRESSING = FOLDER / "pressing.mission"
LINES = MISSION.read_text().splitlines()


@pytest_lsp.fixture(config=ClientServerConfig(
    server_command=[sys.executable, "-m", "robocop_dsl", "lsp"]))
async def client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(types.InitializeParams(
        capabilities=types.ClientCapabilities(),
        workspace_folders=[types.WorkspaceFolder(FOLDER.as_uri(), "lsp")]))
    yield
    await lsp_client.shutdown_session()


async def open_document(client: LanguageClient, text: str | None = None,
                        path: Path = MISSION) -> str:
    """Open the mission at ``path`` (with ``text`` instead of its own) and wait for its
    diagnostics."""
    uri = path.as_uri()
    client.text_document_did_open(types.DidOpenTextDocumentParams(types.TextDocumentItem(
        uri, "mission", 1, path.read_text() if text is None else text)))
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


@pytest.mark.asyncio
async def test_bodies_of_force_torque_and_contact(client: LanguageClient):
    """The body of ``force(...)`` hovers as a body, and its references include the
    bodies of ``torque(...)``, ``contact(...)`` and ``BODY.position``."""
    uri = await open_document(client, path=PRESSING)
    lines = PRESSING.read_text().splitlines()
    number = next(n for n, line in enumerate(lines) if "force(panda_hand).z <" in line)
    use = types.Position(number, lines[number].index("panda_hand"))
    found = await client.text_document_hover_async(types.HoverParams(
        types.TextDocumentIdentifier(uri), use))
    assert "**panda_hand** (body)" in found.contents.value
    references = await client.text_document_references_async(types.ReferenceParams(
        text_document=types.TextDocumentIdentifier(uri), position=use,
        context=types.ReferenceContext(include_declaration=True)))
    places = {(r.range.start.line, r.range.start.character) for r in references
              if r.uri == uri}
    expected = {(n, m.start()) for n, line in enumerate(lines)
                for m in re.finditer(r"\bpanda_hand\b", line)}
    assert places == expected
    assert any("contact(panda_hand" in lines[n] for n, _ in places)


@pytest.mark.parametrize("path", [MISSION, PRESSING], ids=lambda p: p.name)
def test_every_position_answers(path):
    """Hover, definition, references, rename and completion answer at every position of
    a mission with vars, and of its lines cut half way as while typing; the outline and
    the semantic tokens of each state of the text too."""
    text = path.read_text()
    lines = text.split("\n")
    project = Project()
    for number in range(len(lines) + 1):
        cut = lines[number][:len(lines[number]) // 2] if number < len(lines) else ""
        variant = text if number == len(lines) else "\n".join(
            [*lines[:number], cut, *lines[number + 1:]])
        project.open[path] = variant
        parsed = project.parsed(path)
        symbols.document_symbols(parsed.tree)
        semantic_tokens.semantic_tokens(project, parsed)
        where = range(len(lines)) if number == len(lines) else [number]
        for line in where:
            written = variant.split("\n")[line]
            for column in range(len(written) + 1):
                completion.complete(project, path, line, column)
                hover.hover(project, path, line + 1, column + 1)
                navigation.definition(project, path, line + 1, column + 1)
                if navigation.prepare_rename(project, path, line + 1, column + 1):
                    with pytest.raises(JsonRpcInvalidParams):
                        navigation.rename(project, path, line + 1, column + 1, "2nd")
                    navigation.rename(project, path, line + 1, column + 1, "fresh_name")
