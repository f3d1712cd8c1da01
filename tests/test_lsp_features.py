"""The language server's navigation and editing help, driven over stdio: references
and highlights of world names across missions, rename refusals, signature help,
folding, one token type per kind of name, an imported library's unsaved text, and
edits in a row checked once."""

import re
import sys
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pygls.exceptions import JsonRpcInvalidParams
from pytest_lsp import ClientServerConfig, LanguageClient

from robocop_dsl.lsp.semantic_tokens import TOKEN_TYPES

REPO = Path(__file__).resolve().parent.parent
MISSIONS = REPO / "missions"
PICKUP = MISSIONS / "pickup.mission"
LINES = PICKUP.read_text().splitlines()
BODY = "bazar_left_hankamp_tool_object_side"


@pytest_lsp.fixture(config=ClientServerConfig(
    server_command=[sys.executable, "-m", "robocop_dsl", "lsp"]))
async def client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(types.InitializeParams(
        capabilities=types.ClientCapabilities(),
        workspace_folders=[types.WorkspaceFolder(MISSIONS.as_uri(), "missions")]))
    yield
    await lsp_client.shutdown_session()


async def opened(client: LanguageClient, path: Path, text: str | None = None) -> str:
    uri = path.as_uri()
    client.text_document_did_open(types.DidOpenTextDocumentParams(types.TextDocumentItem(
        uri, "mission", 1, path.read_text() if text is None else text)))
    while (await client.wait_for_notification(
            types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)).uri != uri:
        pass
    return uri


def at(text: str, nth: int = 0, lines: list[str] = LINES, after: int = 0) -> types.Position:
    """The position of the ``nth`` line of ``lines`` holding ``text`` (``after``
    characters into it)."""
    number = [n for n, line in enumerate(lines) if text in line][nth]
    return types.Position(number, lines[number].index(text) + after)


@pytest.mark.asyncio
async def test_references_of_a_body_across_missions(client: LanguageClient):
    """A body of the world named in several missions and a library: its references
    are in each of them, and the declaration is its URDF link."""
    uri = await opened(client, PICKUP)
    found = await client.text_document_references_async(types.ReferenceParams(
        text_document=types.TextDocumentIdentifier(uri),
        position=at(f"body_pose({BODY}", after=10),
        context=types.ReferenceContext(include_declaration=True)))
    files = {Path(r.uri).name for r in found}
    assert {"pickup.mission", "bazar_common.mission", "dual_arm.mission",
            "pickup_cascade.mission", "hankamp_tool.urdf"} <= files
    for place in found:
        if place.uri.endswith(".mission"):
            line = Path(place.uri[len("file://"):]).read_text().splitlines()[
                place.range.start.line]
            assert line[place.range.start.character:place.range.end.character] == BODY
    assert len([r for r in found if r.uri == uri]) == sum(
        len(re.findall(rf"\b{BODY}\b", line)) for line in LINES)


@pytest.mark.asyncio
async def test_highlights_of_a_task(client: LanguageClient):
    """The places of the document naming a task: its declaration written, its uses
    read."""
    uri = await opened(client, PICKUP)
    found = await client.text_document_document_highlight_async(types.DocumentHighlightParams(
        types.TextDocumentIdentifier(uri), at("enable arms", after=7)))
    places = {(h.range.start.line, h.kind) for h in found}
    declared = at("task arms").line
    assert (declared, types.DocumentHighlightKind.Write) in places
    assert len(places) == len([line for line in LINES
                               if re.search(r"\barms\b", line.split("#")[0])])


@pytest.mark.asyncio
@pytest.mark.parametrize("where, new_name, reason", [
    ("state approach:", "grasp", "already the state declared at pickup.mission:66"),
    ("final there", "late", "already the final declared at pickup.mission:44"),
    ("task arms", "left_tool", "already the task declared at pickup.mission:29"),
    ("behavior reach(goal: target, precision", "reach", None),
    ("reach(goal: target, precision", "timeout", "already the parameter"),
])
async def test_rename_refused_when_the_name_is_taken(client: LanguageClient, where, new_name,
                                                   reason):
    """Another state of the same machine, another task, another parameter of the same
    behaviour: a rename to its name is refused, saying which it is."""
    uri = await opened(client, PICKUP)
    word = {"state approach:": 6, "final there": 6, "task arms": 5}.get(where, 0)
    position = at(where, after=word if "reach" not in where else
                  (len("behavior ") if where.startswith("behavior") else len("reach(")))
    rename = client.text_document_rename_async(types.RenameParams(
        types.TextDocumentIdentifier(uri), position, new_name))
    if reason is None:
        assert (await rename).changes
        return
    with pytest.raises(JsonRpcInvalidParams, match=reason):
        await rename


@pytest.mark.asyncio
@pytest.mark.parametrize("path, where, after, new_name, reason", [
    (PICKUP, "reach(goal: target", len("reach("), "left_tool",
     "would make an error, .*pickup.mission:39:.*unknown task or constraint"),
    (PICKUP, "let carry_height", len("let "), "pickup_point",
     "would make an error, .*pickup.mission:.*is not a target"),
    (MISSIONS / "bazar_common.mission", "constraint right_speed", len("constraint "),
     "left_hand", "would make an error, .*two_parts.mission:6:.*has the name of a "
                  "constraint"),
])
async def test_rename_refused_when_it_makes_an_error(client: LanguageClient, path, where,
                                                     after, new_name, reason):
    """A clash the naming rules do not see: a behaviour's parameter named as a task its
    body uses, a constant named as a world body the file targets, a library's
    constraint named as a constant of a mission that imports it."""
    uri = await opened(client, path)
    lines = path.read_text().splitlines()
    with pytest.raises(JsonRpcInvalidParams, match=reason):
        await client.text_document_rename_async(types.RenameParams(
            types.TextDocumentIdentifier(uri), at(where, lines=lines, after=after), new_name))


@pytest.mark.asyncio
@pytest.mark.parametrize("line, typed, label, active", [
    ("    interpolator = otg(max_velocity = 1 rad/s, ", "", "otg(", 1),
    ("    interpolator = otg(max_jerk = 1 rad/s^3, max_acc", "", "otg(", 1),
    ("state x: reach(pickup_point, 2 mm, ", "", "reach(goal: target", 2),
    ("task t: body_pose(", "", "body_pose(body)", 0),
    ("    tolerance = pose(position = 1 mm, ", "", "pose(position, orientation)", 1),
    ("    when distance(a, ", "", "distance(body, body)", 1),
    ("    interpolator = otg(max_velocity = [1, ", "", "otg(", 0),
    ("state x: reach(pickup_point offset [0, 0, ", "", "reach(goal: target", 0),
])
async def test_signature_help(client: LanguageClient, tmp_path, line, typed, label, active):
    """Inside a call: its parameters, the one the cursor is on active (by name when
    written ``NAME =``)."""
    text = "\n".join(LINES + [line + typed])
    uri = await opened(client, tmp_path / "typing.mission", text)
    help_ = await client.text_document_signature_help_async(types.SignatureHelpParams(
        types.TextDocumentIdentifier(uri), types.Position(len(LINES), len(line + typed))))
    signature = help_.signatures[0]
    assert signature.label.startswith(label)
    assert help_.active_parameter == active
    assert signature.parameters[active].documentation.value


@pytest.mark.asyncio
async def test_folding_ranges(client: LanguageClient):
    """Blocks fold up to their closing brace, the two rows of a vector and runs of
    comment lines fold too."""
    uri = await opened(client, PICKUP)
    found = await client.text_document_folding_range_async(
        types.FoldingRangeParams(types.TextDocumentIdentifier(uri)))
    ranges = {(r.start_line, r.end_line, r.kind) for r in found}
    task = at("task arms").line
    assert (task, task + 3, None) in ranges
    assert (at("let home_posture").line, at("let home_posture").line + 1, None) in ranges
    state = at("state goto_initial_pose {").line
    assert (state, state + 8, None) in ranges


async def semantic_tokens(client: LanguageClient, uri: str, lines: list[str]
                          ) -> list[tuple[int, str, str]]:
    """The document's semantic tokens, decoded: 0-based line, the word, its type."""
    tokens = await client.text_document_semantic_tokens_full_async(
        types.SemanticTokensParams(types.TextDocumentIdentifier(uri)))
    decoded, line, start = [], 0, 0
    for index in range(0, len(tokens.data), 5):
        delta_line, delta_start, length, kind, _ = tokens.data[index:index + 5]
        line, start = line + delta_line, (start if not delta_line else 0) + delta_start
        decoded.append((line, lines[line][start:start + length], TOKEN_TYPES[kind]))
    return decoded


@pytest.mark.asyncio
async def test_one_token_type_per_kind_of_name(client: LanguageClient):
    """A name has the token type of its kind where it is declared and where it is
    used: a final state after '->', a task after 'enable', a behaviour in an instance,
    a body of the world as a subject and in an action."""
    by_word: dict[str, set] = {}
    for _, word, kind in await semantic_tokens(client, await opened(client, PICKUP), LINES):
        by_word.setdefault(word, set()).add(kind)
    assert by_word["done"] == by_word["there"] == by_word["late"] == {"enumMember"}
    assert by_word["approach"] == by_word["goto_initial_pose"] == {"class"}
    assert by_word["arms"] == {"method"} and by_word["reach"] == {"function"}
    assert by_word[BODY] == by_word["part_body"] == {"struct"}
    assert by_word["bazar_arms"] == {"enum"}
    assert by_word["home_posture"] == {"macro"} and by_word["goal"] == {"parameter"}


@pytest.mark.asyncio
async def test_an_axis_name_has_one_token_type_wherever_it_is_written(client: LanguageClient):
    """'z' in a force task's 'axes = [z]', in 'force(panda_hand).z' and in
    'position.z' is the same word of the vocabulary: one token type, a property, as
    for every setting (it was a variable in the vector)."""
    path = MISSIONS / "panda_press.mission"
    lines = path.read_text().split("\n")
    found: dict[int, set] = {}
    for line, word, kind in await semantic_tokens(client, await opened(client, path), lines):
        if word == "z":
            found.setdefault(line, set()).add(kind)
    written = {number for number, text in enumerate(lines)
               if "[z]" in text or ").z" in text or ".position.z" in text}
    assert set(found) == written and len(written) >= 3
    assert set().union(*found.values()) == {"property"}


@pytest.mark.asyncio
async def test_an_imported_library_is_seen_as_edited(client: LanguageClient):
    """The unsaved text of an open library is what the missions importing it are
    checked against: a task taken out of it is unknown to them at once."""
    mission = MISSIONS / "two_parts.mission"
    library = MISSIONS / "bazar_common.mission"
    mission_uri = await opened(client, mission)
    assert not client.diagnostics[mission_uri]
    library_uri = await opened(client, library)
    text = library.read_text().replace("task left_tool:", "task left_hand:")
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        types.VersionedTextDocumentIdentifier(version=2, uri=library_uri),
        [types.TextDocumentContentChangeWholeDocument(text)]))
    for _ in range(6):
        await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        if "unknown-task" in {d.code for d in client.diagnostics[mission_uri]}:
            break
    assert "unknown-task" in {d.code for d in client.diagnostics[mission_uri]}
    assert not library.read_text().count("left_hand")


@pytest.mark.asyncio
async def test_edits_in_a_row_are_checked_once(client: LanguageClient):
    """Edits sent back to back (a comment typed one character at a time) are checked
    once their burst is over: the diagnostics published are for the last version, and
    far fewer than the edits."""
    uri = await opened(client, PICKUP)
    published: list[int] = []
    edits, line = 60, len(LINES)
    for version in range(2, edits + 2):
        at_end = types.Position(line, version - 2)
        client.text_document_did_change(types.DidChangeTextDocumentParams(
            types.VersionedTextDocumentIdentifier(version=version, uri=uri),
            [types.TextDocumentContentChangePartial(types.Range(at_end, at_end), "#")]))
    while not published or published[-1] != edits + 1:
        params = await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        published.append(params.version)
    assert len(published) < edits / 4
    assert not client.diagnostics[uri]


@pytest.mark.asyncio
async def test_a_behaviour_final_is_named_and_renamed_where_it_is_instantiated(
        client: LanguageClient):
    """A library behaviour's final state is named by the missions that instantiate it
    (``first.placed``): its references, asked for there, are in both files, and a
    rename from there edits both."""
    mission, library = MISSIONS / "two_parts.mission", MISSIONS / "bazar_common.mission"
    lines = mission.read_text().splitlines()
    uri = await opened(client, mission)
    position = at("first.placed", lines=lines, after=len("first."))
    found = await client.text_document_references_async(types.ReferenceParams(
        text_document=types.TextDocumentIdentifier(uri), position=position,
        context=types.ReferenceContext(include_declaration=True)))
    places = {(Path(p.uri).name, p.range.start.line) for p in found}
    library_lines = library.read_text().splitlines()
    assert (library.name, at("final placed", lines=library_lines).line) in places
    assert (mission.name, position.line) in places
    edit = await client.text_document_rename_async(types.RenameParams(
        types.TextDocumentIdentifier(uri), position, "delivered"))
    assert {Path(u).name for u in edit.changes} >= {mission.name, library.name}
