"""The language server started as the VS Code extension starts it: the command line it
builds (editors/vscode/server.js, run with node), ``--stdio`` appended as the language
client appends it, spoken to over stdio; the other transports refused."""

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from lsprotocol import types
from pytest_lsp import make_test_lsp_client

REPO = Path(__file__).resolve().parent.parent
EXTENSION = REPO / "editors" / "vscode"
PICKUP = REPO / "missions" / "pickup.mission"


def extension_command(*interpreter: str) -> list[str]:
    """The command line the extension builds, with the Python interpreter given (as
    the Python extension would give it) or none."""
    found = subprocess.run(["node", "test/command.js", *interpreter], cwd=EXTENSION,
                           capture_output=True, text=True, check=True)
    return json.loads(found.stdout)


@pytest.mark.skipif(shutil.which("node") is None, reason="needs node")
@pytest.mark.asyncio
@pytest.mark.parametrize("interpreter", [(sys.executable,), ()],
                         ids=["python extension's interpreter", "robocop-mission on PATH"])
async def test_the_extension_command_line_serves(interpreter):
    """The exact command line the extension runs starts a server that answers: its
    diagnostics for a mission, then ``shutdown`` and ``exit`` end it with code 0."""
    if not interpreter and shutil.which("robocop-mission") is None:
        pytest.skip("robocop-mission is not on PATH")
    command = extension_command(*interpreter)
    assert command[-1] == "--stdio"
    if interpreter:
        assert command == [sys.executable, "-m", "robocop_dsl", "lsp", "--stdio"]
    client = make_test_lsp_client()
    await client.start_io(*command)
    await client.initialize_session(types.InitializeParams(
        capabilities=types.ClientCapabilities()))
    client.text_document_did_open(types.DidOpenTextDocumentParams(types.TextDocumentItem(
        PICKUP.as_uri(), "mission", 1, PICKUP.read_text().replace("-> done", "-> dne"))))
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    assert "unknown-state" in {d.code for d in client.diagnostics[PICKUP.as_uri()]}
    await client.shutdown_session()
    assert client._server.returncode == 0


@pytest.mark.parametrize("option", ["--socket=5007", "--pipe=/tmp/robocop.sock", "--node-ipc"])
def test_other_transports_are_refused(option):
    """Only stdio is served: another transport is a usage error that says so."""
    run = subprocess.run([sys.executable, "-m", "robocop_dsl", "lsp", option,
                          "--clientProcessId=42"], capture_output=True, text=True,
                         stdin=subprocess.DEVNULL)
    assert run.returncode == 2
    assert f"{option.split('=')[0]}: this server speaks the Language Server Protocol over " \
           "stdio only" in run.stderr
    assert "Traceback" not in run.stderr


def test_client_process_id_is_accepted():
    """``--clientProcessId`` (which clients add) is taken; the server ends when its
    input ends."""
    run = subprocess.run([sys.executable, "-m", "robocop_dsl", "lsp", "--stdio",
                          "--clientProcessId=42"], capture_output=True, text=True,
                         stdin=subprocess.DEVNULL)
    assert run.returncode == 0, run.stderr


@pytest.mark.skipif(shutil.which("node") is None, reason="needs node")
def test_the_extension_finds_the_server_in_its_order():
    """editors/vscode/test/server.test.js, with node's test runner: the settings (a
    program's path, its name on PATH, ``~/`` and ``${workspaceFolder}``), the Python
    extension's interpreter, PATH, what is said when nothing is found, and, once
    ``npm ci`` has installed the language client, that it appends ``--stdio``."""
    done = subprocess.run(["node", "--test", "test/server.test.js"], cwd=EXTENSION,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    counts = {name: int(count) for name, count in
              re.findall(r"^# (pass|fail|skipped) (\d+)$", done.stdout, re.M)}
    assert counts["fail"] == 0 and counts["pass"] >= 7
    assert counts["pass"] + counts["skipped"] >= 8    # the client's own code: after npm ci
