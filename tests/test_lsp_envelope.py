"""Messages that are not JSON-RPC 2.0, written as raw frames to the server's stdin: each
gets an "invalid request" error (with its id when it is a request whose id can be
read, else with a null id), never an error shown to the user, and the server goes on.
A notification whose parameters do not fit is ignored, saying why in the log."""

import json
import os
import queue
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
SERVER = [sys.executable, "-m", "robocop_dsl", "lsp", "--stdio"]
TIMEOUT = 30.0
"""The longest wait for a message [s]."""


class Frames:
    """A server read on a thread of its own, so that every wait has a deadline."""

    def __init__(self):
        paths = os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))
        self.process = subprocess.Popen(SERVER, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                        stderr=subprocess.DEVNULL, cwd=REPO,
                                        env={**os.environ, "PYTHONPATH": paths})
        self.received: queue.Queue = queue.Queue()
        self.seen: list[dict] = []
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        stdout = self.process.stdout
        while True:
            length = None
            while (line := stdout.readline()) not in (b"\r\n", b""):
                if line.lower().startswith(b"content-length:"):
                    length = int(line.split(b":")[1])
            if length is None:
                return
            self.received.put(json.loads(stdout.read(length)))

    def send_bytes(self, body: bytes) -> None:
        self.process.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
        self.process.stdin.flush()

    def send(self, message) -> None:
        self.send_bytes(json.dumps(message).encode())

    def until(self, predicate) -> dict:
        """The first message from now on that ``predicate`` accepts (every one read is
        kept in ``seen``)."""
        deadline = time.monotonic() + TIMEOUT
        while True:
            try:
                message = self.received.get(timeout=max(deadline - time.monotonic(), 0))
            except queue.Empty:
                raise AssertionError("no such message from the server") from None
            self.seen.append(message)
            if predicate(message):
                return message

    def answer(self, msg_id) -> dict:
        return self.until(lambda m: "method" not in m and m.get("id") == msg_id)


@pytest.fixture
def frames():
    server = Frames()
    server.send({"jsonrpc": "2.0", "id": 1, "method": "initialize",
                 "params": {"processId": None, "rootUri": None, "capabilities": {}}})
    server.answer(1)
    server.send({"jsonrpc": "2.0", "method": "initialized", "params": {}})
    server.seen.clear()
    yield server
    server.process.kill()
    server.process.wait()


HOVER = {"textDocument": {"uri": (REPO / "missions" / "pickup.mission").as_uri()},
         "position": {"line": 0, "character": 0}}


@pytest.mark.parametrize("body, answered_id", [
    (b"[]", None),
    (b"[1, 2]", None),
    (b"42", None),
    (b'"hover"', None),
    (b"null", None),
    (json.dumps({"jsonrpc": "2.0", "id": 107, "method": 5}).encode(), 107),
    (json.dumps({"jsonrpc": "1.0", "id": 106, "method": "textDocument/hover",
                 "params": HOVER}).encode(), 106),
    (json.dumps({"id": 105, "method": "textDocument/hover", "params": HOVER}).encode(), 105),
    (json.dumps({"jsonrpc": "2.0", "id": {"a": 1}, "method": "textDocument/hover",
                 "params": HOVER}).encode(), None),
    (json.dumps({"jsonrpc": "2.0", "id": True, "method": "shutdown"}).encode(), None),
    (json.dumps({"jsonrpc": "2.0", "method": 5}).encode(), None),
    (json.dumps({"jsonrpc": "1.0", "method": "initialized", "params": {}}).encode(), None),
    (json.dumps({"jsonrpc": "1.0", "id": 104, "result": None}).encode(), None),
    (json.dumps({"jsonrpc": "2.0", "id": 103, "method": "initialized",
                 "params": {}}).encode(), 103),
    (json.dumps({"jsonrpc": "2.0", "id": 102, "method": "$/cancelRequest",
                 "params": {"id": 5}}).encode(), 102),
    (json.dumps({"jsonrpc": "2.0", "id": "s", "method": "$/setTrace",
                 "params": {"value": "off"}}).encode(), "s"),
], ids=["empty array", "array", "number", "string", "null", "method not a string",
        "version 1.0", "no version", "id an object", "id a boolean",
        "notification with a method not a string", "notification of version 1.0",
        "response of version 1.0", "initialized with an id", "cancelRequest with an id",
        "setTrace with an id"])
def test_a_message_that_is_not_json_rpc_2_gets_an_invalid_request_error(
        frames, body, answered_id):
    frames.send_bytes(body)
    error = frames.until(lambda m: "error" in m and "method" not in m)
    assert error["id"] == answered_id and error["error"]["code"] == -32600
    assert error["jsonrpc"] == "2.0" and error["error"]["message"]
    frames.send({"jsonrpc": "2.0", "id": 200, "method": "textDocument/hover",
                 "params": HOVER})
    assert "error" not in frames.answer(200)
    assert not [m for m in frames.seen if m.get("method") == "window/showMessage"]


def test_an_object_inside_a_message_is_never_read_as_a_message(frames):
    """Only the whole message is one: an object of its parameters that looks like a
    message is a parameter."""
    inner = {"jsonrpc": "2.0", "id": 3}
    frames.send({"jsonrpc": "2.0", "id": 201, "method": "textDocument/hover",
                 "params": {**HOVER, "extra": inner}})
    assert "error" not in frames.answer(201)
    assert [m["id"] for m in frames.seen if "method" not in m] == [201]


def test_a_notification_whose_parameters_do_not_fit_is_ignored_in_the_log(frames):
    for params in [{"textDocument": 5}, None]:
        frames.send({"jsonrpc": "2.0", "method": "textDocument/didChange", "params": params})
        logged = frames.until(lambda m: m.get("method") == "window/logMessage")
        assert logged["params"]["message"].startswith("textDocument/didChange ignored: ")
    frames.send({"jsonrpc": "2.0", "id": 202, "method": "textDocument/hover",
                 "params": HOVER})
    assert "error" not in frames.answer(202)
    assert not [m for m in frames.seen if m.get("method") == "window/showMessage"]
