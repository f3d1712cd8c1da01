"""The language server driven by a real LSP client over stdio: diagnostics as the text
changes, completion, hover, definition, references, rename, outline, formatting."""

import json
import subprocess
import sys
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient

REPO = Path(__file__).resolve().parent.parent
MISSIONS = REPO / "missions"

BROKEN = '''mission broken "Two mistakes."

world "bazar/sophia.yaml"

task tool: body_pose(bazar_left_hankamp_tool_objet_side) {
    interpolator = otg(max_velocity = 0.2 m/s, max_acceleration = 0.5 m/s^2)
}

state go {
    enter { enable tool }
    when tool.reached -> dne
}

final done
'''


@pytest_lsp.fixture(config=ClientServerConfig(
    server_command=[sys.executable, "-m", "robocop_dsl", "lsp"]))
async def client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(types.InitializeParams(
        capabilities=types.ClientCapabilities(),
        workspace_folders=[types.WorkspaceFolder(MISSIONS.as_uri(), "missions")]))
    yield
    await lsp_client.shutdown_session()


async def open_document(client: LanguageClient, path: Path, text: str | None = None):
    """Open ``path`` and wait for its first diagnostics."""
    uri = path.as_uri()
    client.text_document_did_open(types.DidOpenTextDocumentParams(types.TextDocumentItem(
        uri, "mission", 1, path.read_text() if text is None else text)))
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    return uri


def position(path: Path, line: int, word: str, after: int = 0) -> types.Position:
    """The 0-based position of ``word`` on 1-based ``line`` of ``path`` (plus ``after``)."""
    return types.Position(line - 1, path.read_text().splitlines()[line - 1].index(word) + after)


@pytest.mark.asyncio
async def test_diagnostics_come_and_go(client: LanguageClient, tmp_path):
    """A broken mission gets every diagnostic ``check`` gives, at its place, with its
    code and hint; fixing the text clears them."""
    path = tmp_path / "broken.mission"
    path.write_text(BROKEN)
    uri = await open_document(client, path)
    found = {(d.code, d.range.start.line, d.range.start.character, d.range.end.character)
             for d in client.diagnostics[uri]}
    assert {("unknown-body", 4, 21, 55), ("unknown-state", 10, 25, 28)} <= found
    checked = json.loads(subprocess.run(
        [sys.executable, "-m", "robocop_dsl", "check", "--format", "json", str(path)],
        capture_output=True, text=True).stdout)[0]["diagnostics"]
    assert found == {(d["code"], d["span"]["line"] - 1, d["span"]["column"] - 1,
                      d["span"]["end_column"] - 1) for d in checked}
    body = next(d for d in client.diagnostics[uri] if d.code == "unknown-body")
    assert "did you mean 'bazar_left_hankamp_tool_object_side'?" in body.message
    assert body.severity == types.DiagnosticSeverity.Error

    fixed = BROKEN.replace("objet", "object").replace("dne", "done")
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        types.VersionedTextDocumentIdentifier(version=2, uri=uri),
        [types.TextDocumentContentChangeWholeDocument(fixed)]))
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    assert not client.diagnostics[uri]


@pytest.mark.asyncio
async def test_behavior_instance_note_is_related_information(client: LanguageClient):
    """A problem inside a behaviour names the instance that exposed it as related
    information, at that instance's place."""
    path = REPO / "tests" / "fixtures" / "invalid" / "composite_behavior_problem.mission"
    uri = await open_document(client, path)
    dimension = next(d for d in client.diagnostics[uri] if d.code == "wrong-dimension")
    assert dimension.range.start.line == 12
    related = dimension.related_information
    assert related[0].message.startswith("in approach(left_tool, pickup_point) at ")
    assert related[0].location.uri == uri
    assert related[0].location.range.start.line == 24


@pytest.mark.asyncio
async def test_completion_of_task_types_and_bodies(client: LanguageClient, tmp_path):
    """After ``task x: `` the task types are offered; after ``body_pose(`` the world's
    bodies."""
    path = tmp_path / "typing.mission"
    text = 'mission m\nworld "bazar/sophia.yaml"\ntask x: \n'
    path.write_text(text)
    uri = await open_document(client, path)
    result = await client.text_document_completion_async(types.CompletionParams(
        types.TextDocumentIdentifier(uri), types.Position(2, 8)))
    labels = {item.label for item in result.items}
    assert {"joint_position", "body_pose", "gaze"} <= labels
    assert "joint_kinematic" not in labels

    typed = text.replace("task x: ", "task x: body_pose(")
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        types.VersionedTextDocumentIdentifier(version=2, uri=uri),
        [types.TextDocumentContentChangeWholeDocument(typed)]))
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    result = await client.text_document_completion_async(types.CompletionParams(
        types.TextDocumentIdentifier(uri), types.Position(2, 18)))
    labels = {item.label for item in result.items}
    assert {"bazar_left_hankamp_tool_object_side", "pickup_point", "world"} <= labels
    assert "bazar_arms" not in labels


@pytest.mark.asyncio
async def test_completion_of_parameters_with_units(client: LanguageClient):
    """Inside a constraint's block its parameters are offered with their units."""
    path = MISSIONS / "pickup.mission"
    uri = await open_document(client, path)
    result = await client.text_document_completion_async(types.CompletionParams(
        types.TextDocumentIdentifier(uri), types.Position(18, 4)))
    details = {item.label: item.detail for item in result.items}
    assert details["max_linear"] == "linear velocity: m/s, cm/s, mm/s"
    assert {"reference", "max_linear", "max_angular"} <= set(details)
    assert "max_velocity" not in details and "enable" not in details


@pytest.mark.asyncio
async def test_hover(client: LanguageClient):
    """Hover shows a task type's parameters, a body's parent and place, a constant's
    value."""
    path = MISSIONS / "pickup.mission"
    uri = await open_document(client, path)

    async def hover(line, word):
        found = await client.text_document_hover_async(types.HoverParams(
            types.TextDocumentIdentifier(uri), position(path, line, word, 1)))
        return found.contents.value

    otg = await hover(24, "otg")
    assert "online trajectory generation" in otg
    assert "- `max_velocity` (velocity of what the interpolator drives; required)" in otg
    body = await hover(29, "bazar_left_hankamp_tool_object_side")
    assert "parent: `bazar_left_hankamp_tool_robot_side`" in body
    assert "world position at the initial configuration" in body
    assert "let approach_height = 10 cm" in await hover(60, "approach_height")


@pytest.mark.asyncio
async def test_definition_across_an_import(client: LanguageClient):
    """A task and a behaviour declared in an imported file, and a body of the world."""
    path = MISSIONS / "two_parts.mission"
    uri = await open_document(client, path)
    common = (MISSIONS / "bazar_common.mission").as_uri()

    async def definition(line, word):
        found = await client.text_document_definition_async(types.DefinitionParams(
            types.TextDocumentIdentifier(uri), position(path, line, word)))
        return [(f.uri, f.range.start.line) for f in found]

    lines = (MISSIONS / "bazar_common.mission").read_text().splitlines()
    declared = {word: next(i for i, line in enumerate(lines) if line.startswith(word))
                for word in ("task left_tool", "behavior go_home")}
    assert await definition(14, "left_tool") == [(common, declared["task left_tool"])]
    assert await definition(8, "go_home") == [(common, declared["behavior go_home"])]
    world = (REPO / "robots" / "bazar" / "two_parts.yaml").resolve()
    target = await definition(14, "pickup_point")
    assert target[0][0].endswith(".yaml") and Path(target[0][0][7:]).exists()
    assert (await definition(3, "bazar"))[0][0] == world.as_uri()


@pytest.mark.asyncio
async def test_references_and_rename_across_files(client: LanguageClient):
    """Renaming a task declared in a library edits the library and every mission that
    imports it, and nothing else."""
    path = MISSIONS / "two_parts.mission"
    uri = await open_document(client, path)
    at = position(path, 14, "left_tool")
    references = await client.text_document_references_async(types.ReferenceParams(
        text_document=types.TextDocumentIdentifier(uri), position=at,
        context=types.ReferenceContext(include_declaration=True)))
    files = {Path(r.uri).name for r in references}
    assert {"two_parts.mission", "bazar_common.mission"} <= files
    assert "pickup.mission" not in files       # it declares a left_tool of its own

    edit = await client.text_document_rename_async(types.RenameParams(
        types.TextDocumentIdentifier(uri), at, "left_gripper"))
    changes = {Path(u).name: edits for u, edits in edit.changes.items()}
    assert set(changes) == files
    two_parts = path.read_text().splitlines()
    for change in changes["two_parts.mission"]:
        line = two_parts[change.range.start.line]
        assert line[change.range.start.character:change.range.end.character] == "left_tool"
    assert len(changes["two_parts.mission"]) == path.read_text().count("left_tool")


@pytest.mark.asyncio
async def test_outline(client: LanguageClient):
    """The outline lists declarations and states, nested states inside theirs."""
    path = MISSIONS / "pickup.mission"
    uri = await open_document(client, path)
    symbols = await client.text_document_document_symbol_async(
        types.DocumentSymbolParams(types.TextDocumentIdentifier(uri)))
    names = [s.name for s in symbols]
    assert names[:4] == ["home_posture", "approach_height", "carry_height", "joint_limits"]
    reach = next(s for s in symbols if s.name == "reach")
    assert [c.name for c in reach.children] == ["moving", "there", "late"]


@pytest.mark.asyncio
async def test_formatting_keeps_comments(client: LanguageClient, tmp_path):
    """Formatting normalises spacing and blocks, keeps every comment and adds no blank
    line."""
    path = tmp_path / "messy.mission"
    path.write_text('# a mission\nmission  m\nworld "bazar/sophia.yaml"   # the robot\n'
                    "task  arms : joint_position( bazar_arms ) {priority=1}\n"
                    "state s {\n  # wait\nwhen arms.reached->done }\nfinal done\n")
    uri = await open_document(client, path)
    edits = await client.text_document_formatting_async(types.DocumentFormattingParams(
        types.TextDocumentIdentifier(uri), types.FormattingOptions(4, True)))
    assert edits[0].new_text == (
        '# a mission\nmission m\nworld "bazar/sophia.yaml"  # the robot\n'
        "task arms: joint_position(bazar_arms) {\n    priority = 1\n}\n"
        "state s {\n    # wait\n    when arms.reached -> done\n}\nfinal done\n")
