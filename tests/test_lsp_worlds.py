"""The language server loads each world once and again when one of its files changes."""

import shutil
import sys
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient

REPO = Path(__file__).resolve().parent.parent
MISSION = '''mission {name}
world "bazar/sophia.yaml"
task arms: joint_position(spare_arm)
state s {{
    enter {{ enable arms }}
    when arms.reached -> done
}}
final done
'''


@pytest_lsp.fixture(config=ClientServerConfig(
    server_command=[sys.executable, "-m", "robocop_dsl", "lsp"]))
async def client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(types.InitializeParams(
        capabilities=types.ClientCapabilities()))
    yield
    await lsp_client.shutdown_session()


async def opened(client: LanguageClient, path: Path) -> list:
    client.text_document_did_open(types.DidOpenTextDocumentParams(types.TextDocumentItem(
        path.as_uri(), "mission", 1, path.read_text())))
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    return [d.code for d in client.diagnostics[path.as_uri()]]


@pytest.mark.asyncio
async def test_world_loaded_once_and_reloaded_on_change(client: LanguageClient, tmp_path):
    """Two missions on one world load it once; a new joint group written in the world
    file is seen at the next check, after one reload."""
    shutil.copytree(REPO / "robots" / "bazar", tmp_path / "bazar")
    first, second = tmp_path / "first.mission", tmp_path / "second.mission"
    first.write_text(MISSION.format(name="first"))
    second.write_text(MISSION.format(name="second"))
    assert await opened(client, first) == ["unknown-joint-group"]
    assert await opened(client, second) == ["unknown-joint-group"]
    loads = [m.message for m in client.log_messages if m.message.startswith("loaded world")]
    assert loads == [f"loaded world {(tmp_path / 'bazar' / 'sophia.yaml').resolve()}"]

    world = tmp_path / "bazar" / "sophia.yaml"
    text = world.read_text()
    assert "\njoint_groups:" not in text
    world.write_text(text + "joint_groups:\n  spare_arm: [bazar_left_arm]\n")
    client.text_document_did_save(types.DidSaveTextDocumentParams(
        types.TextDocumentIdentifier(first.as_uri())))
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    assert not client.diagnostics[first.as_uri()]
    loads = [m.message for m in client.log_messages if m.message.startswith("loaded world")]
    assert len(loads) == 2
