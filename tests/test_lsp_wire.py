"""The language server on the wire, as clients that get things wrong meet it: bytes
that are not JSON, a message that is neither request nor response, requests after
``shutdown``, quick-fix data the server did not write, a document opened through a
symbolic link, lone carriage returns, and an editor that dies without a word."""

import json
import subprocess
import sys
import time
from pathlib import Path

import pytest
from lsprotocol import types
from pygls.exceptions import JsonRpcInvalidParams
from pytest_lsp import make_test_lsp_client

REPO = Path(__file__).resolve().parent.parent
MISSIONS = REPO / "missions"
SERVER = [sys.executable, "-m", "robocop_dsl", "lsp", "--stdio"]


class Wire:
    """A server driven with raw JSON-RPC frames over its stdin and stdout."""

    def __init__(self, *options: str):
        self.process = subprocess.Popen(SERVER + list(options), stdin=subprocess.PIPE,
                                        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)

    def send_bytes(self, body: bytes) -> None:
        self.process.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
        self.process.stdin.flush()

    def send(self, message: dict) -> None:
        self.send_bytes(json.dumps({"jsonrpc": "2.0", **message}).encode())

    def receive(self) -> dict:
        length = 0
        while (line := self.process.stdout.readline()) not in (b"\r\n", b""):
            if line.lower().startswith(b"content-length:"):
                length = int(line.split(b":")[1])
        return json.loads(self.process.stdout.read(length))

    def reply(self, predicate) -> dict:
        """The first message read that ``predicate`` accepts (notifications skipped)."""
        while not predicate(message := self.receive()):
            pass
        return message

    def request(self, msg_id: int, method: str, params=None) -> dict:
        self.send({"id": msg_id, "method": method, "params": params})
        return self.reply(lambda m: m.get("id") == msg_id and "method" not in m)

    def initialize(self) -> None:
        self.request(1, "initialize", {"processId": None, "rootUri": None,
                                       "capabilities": {}})
        self.send({"method": "initialized", "params": {}})

    def close(self) -> int:
        self.process.stdin.close()
        return self.process.wait(timeout=60)


@pytest.fixture
def wire():
    server = Wire()
    server.initialize()
    yield server
    if server.process.poll() is None:
        server.process.kill()
        server.process.wait()


def test_bytes_that_are_not_json_get_a_parse_error_and_the_server_goes_on(wire):
    wire.send_bytes(b'{"jsonrpc": "2.0", "id": 5, "method": ')
    answer = wire.reply(lambda m: "error" in m)
    assert answer["id"] is None and answer["error"]["code"] == -32700
    assert wire.request(6, "shutdown")["result"] is None


def test_a_message_without_method_result_or_error_is_an_invalid_request(wire):
    wire.send({"id": 9})
    answer = wire.reply(lambda m: m.get("id") == 9)
    assert answer["error"]["code"] == -32600


@pytest.mark.parametrize("line, refused", [(1.5, "1.5 is not an integer"),
                                           (True, "True is not an integer"),
                                           ("3", "'3' is not an integer"),
                                           (2.0, None)])
def test_a_position_that_is_not_an_integer_is_refused_not_rounded(wire, line, refused):
    """A position must be an integer (JSON's 2.0 is one): a fraction, a boolean or a
    string gets an 'invalid params' error for every request that takes a position,
    where it used to be rounded (a hover on another line) or converted."""
    uri = (MISSIONS / "pickup.mission").as_uri()
    wire.send({"method": "textDocument/didOpen", "params": {"textDocument": {
        "uri": uri, "languageId": "robocop-mission", "version": 1,
        "text": (MISSIONS / "pickup.mission").read_text()}}})
    at = {"textDocument": {"uri": uri}, "position": {"line": line, "character": 4}}
    for msg_id, method in enumerate(["textDocument/hover", "textDocument/completion",
                                     "textDocument/definition", "textDocument/references",
                                     "textDocument/signatureHelp"], 10):
        context = {"context": {"includeDeclaration": True}} if "references" in method else {}
        answer = wire.request(msg_id, method, {**at, **context})
        if refused is None:
            assert "error" not in answer
        else:
            assert answer["error"]["code"] == -32602
            assert refused in answer["error"]["message"]


def test_options_that_are_not_integers_or_booleans_are_refused(wire):
    """Formatting options and a diagnostic's severity are checked as strictly; the
    server's own diagnostics still come back through a quick fix (their severity is an
    enumeration of integers)."""
    uri = (MISSIONS / "pickup.mission").as_uri()
    wire.send({"method": "textDocument/didOpen", "params": {"textDocument": {
        "uri": uri, "languageId": "robocop-mission", "version": 1,
        "text": (MISSIONS / "pickup.mission").read_text().replace("-> grasp", "-> grsp")}}})
    published = wire.reply(lambda m: m.get("method") == "textDocument/publishDiagnostics")
    diagnostic = next(d for d in published["params"]["diagnostics"]
                      if d["code"] == "unknown-state")
    document = {"textDocument": {"uri": uri}}
    for msg_id, options in enumerate([{"tabSize": 4.5, "insertSpaces": True},
                                      {"tabSize": 4, "insertSpaces": 1}], 20):
        answer = wire.request(msg_id, "textDocument/formatting", {**document,
                                                                  "options": options})
        assert answer["error"]["code"] == -32602
    fix = {**document, "range": diagnostic["range"], "context": {"diagnostics": [diagnostic]}}
    [action] = wire.request(30, "textDocument/codeAction", fix)["result"]
    assert action["diagnostics"] == [diagnostic] and action["isPreferred"] is True
    bad = {**fix, "context": {"diagnostics": [{**diagnostic, "severity": 1.5}]}}
    assert wire.request(31, "textDocument/codeAction", bad)["error"]["code"] == -32602


def test_requests_after_shutdown_are_refused_and_exit_ends_with_code_0(wire):
    assert wire.request(2, "shutdown")["result"] is None
    uri = (MISSIONS / "pickup.mission").as_uri()
    for msg_id, method, params in [
            (3, "textDocument/hover", {"textDocument": {"uri": uri},
                                       "position": {"line": 0, "character": 0}}),
            (4, "shutdown", None)]:
        answer = wire.request(msg_id, method, params)
        assert answer["error"]["code"] == -32600
        assert "shut down" in answer["error"]["message"]
    wire.send({"method": "exit"})
    assert wire.process.wait(timeout=60) == 0


def test_the_server_exits_once_the_editor_process_is_gone():
    """``--clientProcessId`` names the editor: when that process ends, so does the
    server (code 1: it was not shut down)."""
    editor = subprocess.Popen([sys.executable, "-c", "import sys; sys.stdin.read()"],
                              stdin=subprocess.PIPE)
    server = Wire(f"--clientProcessId={editor.pid}")
    server.initialize()
    assert server.process.poll() is None
    editor.stdin.close()
    editor.wait(timeout=60)
    assert server.process.wait(timeout=60) == 1


async def started():
    client = make_test_lsp_client()
    await client.start_io(*SERVER)
    await client.initialize_session(types.InitializeParams(
        capabilities=types.ClientCapabilities()))
    return client


async def published(client, uri: str) -> list[types.Diagnostic]:
    while True:
        found = await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        if found.uri == uri:
            return found.diagnostics


def opened(client, uri: str, text: str) -> None:
    client.text_document_did_open(types.DidOpenTextDocumentParams(
        types.TextDocumentItem(uri, "mission", 1, text)))


@pytest.mark.asyncio
async def test_a_document_opened_through_a_link_keeps_its_uri(tmp_path):
    """Diagnostics and references name an open document by the URI the editor used,
    not by where a symbolic link leads."""
    (tmp_path / "real").mkdir()
    mission = tmp_path / "real" / "typo.mission"
    text = (MISSIONS / "pickup.mission").read_text().replace(
        "bazar/sophia.yaml", str(REPO / "robots" / "bazar" / "sophia.yaml"))
    mission.write_text(text.replace("left_tool.reached and", "left_tool.reachd and", 1))
    (tmp_path / "link").symlink_to(tmp_path / "real")
    uri = (tmp_path / "link" / "typo.mission").as_uri()
    client = await started()
    opened(client, uri, mission.read_text())
    diagnostics = await published(client, uri)
    assert any(d.code == "unknown-field" or "reachd" in d.message for d in diagnostics)
    line = next(i for i, row in enumerate(text.splitlines()) if "task left_tool" in row)
    column = text.splitlines()[line].index("left_tool")
    found = await client.text_document_references_async(types.ReferenceParams(
        text_document=types.TextDocumentIdentifier(uri),
        position=types.Position(line, column),
        context=types.ReferenceContext(include_declaration=True)))
    assert found and {place.uri for place in found} == {uri}
    await client.shutdown_session()


@pytest.mark.asyncio
async def test_quick_fix_data_the_server_did_not_write_is_refused(tmp_path):
    client = await started()
    path = tmp_path / "m.mission"
    path.write_text("mission m\n")
    uri = path.as_uri()
    opened(client, uri, path.read_text())
    await published(client, uri)
    document = types.TextDocumentIdentifier(uri)
    whole = types.Range(types.Position(0, 0), types.Position(0, 1))
    fix = {"title": "t", "uri": uri, "line": 999, "column": 1, "end_line": 999,
           "end_column": 3, "text": "x", "preferred": True}
    for data, reason in [("garbage", "not this server's quick fixes"),
                         ([{"title": "t"}], "not this server's quick fixes"),
                         ([fix], "is not in m.mission")]:
        diagnostic = types.Diagnostic(whole, "x", source="robocop-mission", data=data)
        with pytest.raises(JsonRpcInvalidParams, match=reason):
            await client.text_document_code_action_async(types.CodeActionParams(
                document, whole, types.CodeActionContext([diagnostic])))
    other = types.Diagnostic(whole, "x", source="another-linter", data="its own")
    assert not await client.text_document_code_action_async(types.CodeActionParams(
        document, whole, types.CodeActionContext([other])))
    with pytest.raises(JsonRpcInvalidParams, match="past the end"):
        await client.text_document_code_action_async(types.CodeActionParams(
            document, types.Range(types.Position(50, 0), types.Position(50, 0)),
            types.CodeActionContext([])))
    await client.shutdown_session()


@pytest.mark.asyncio
async def test_a_lone_carriage_return_ends_a_line_as_the_editor_counts_it(tmp_path):
    """Editors count ``\\r`` alone as a line break: so do the server and ``check``."""
    path = tmp_path / "cr.mission"
    text = ('mission cr\r\nworld "' + str(REPO / "robots/bazar/sophia.yaml") + '"\n'
            "# a comment\rstate s {\n    when elapsed > 1 s -> nowhere\n}\n")
    path.write_bytes(text.encode())
    client = await started()
    uri = path.as_uri()
    opened(client, uri, text)
    diagnostics = await published(client, uri)
    unknown = next(d for d in diagnostics if "nowhere" in d.message)
    assert unknown.range.start.line == 4
    await client.shutdown_session()
    done = subprocess.run([sys.executable, "-m", "robocop_dsl", "check", str(path)],
                          capture_output=True, text=True)
    assert done.returncode == 1 and f"{path}:5:27: error[unknown-state]" in done.stdout
