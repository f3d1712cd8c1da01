"""The JSON-RPC side of the server: pygls's protocol, with a request whose parameters
are not valid (a negative or fractional position, one past 2^31 - 1, a missing
field), a message that is not a request, a notification or a response, and a request
after ``shutdown`` answered by an error that says what is wrong instead of being
dropped, and the documents' texts left to the server (pygls's own copies, rebuilt
line by line at each change, are not kept)."""

from __future__ import annotations

import logging

from lsprotocol import types
from pygls.exceptions import (JsonRpcInvalidParams, JsonRpcInvalidRequest,
                              JsonRpcParseError, JsonRpcRequestCancelled)
from pygls.protocol import LanguageServerProtocol, default_converter, lsp_method

_MESSAGE_KEYS = ("method", "result", "error")
"""A JSON-RPC message has one of these: a request or notification, or a response."""


class _Answered:
    """A request already answered with an error: there is nothing left to handle."""

    jsonrpc = None


def _integer(value, kind: type) -> int:
    """An integer field's value: a JSON integer (``2.0`` counts), never a fraction, a
    boolean or a string, which cattrs would otherwise round or convert. ``kind`` is
    ``int`` or one of its subclasses (an ``IntEnum`` such as a diagnostic's severity),
    which the value is made into."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not float(value).is_integer():
        raise ValueError(f"{value!r} is not an integer")
    return kind(int(value))


def _boolean(value, _kind) -> bool:
    """A boolean field's value: ``true`` or ``false``, not a number cattrs would convert."""
    if not isinstance(value, bool):
        raise ValueError(f"{value!r} is not a boolean")
    return value


def converter():
    """pygls's converter, strict about integers (positions, versions, enumerations'
    values) and booleans."""
    made = default_converter()
    made.register_structure_hook(int, _integer)
    made.register_structure_hook(bool, _boolean)
    return made


def _reasons(error: BaseException) -> list[str]:
    """The innermost messages of a (grouped) validation error."""
    inner = getattr(error, "exceptions", None)
    if not inner:
        return [str(error)]
    return [reason for item in inner for reason in _reasons(item)]


class MissionProtocol(LanguageServerProtocol):
    """pygls's language server protocol; malformed requests get an error reply."""

    def structure_message(self, data: dict):
        if "jsonrpc" in data and "id" in data and not any(k in data for k in _MESSAGE_KEYS):
            return self._refuse(data["id"], JsonRpcInvalidRequest(
                "invalid message: it has no 'method', 'result' or 'error'"))
        kind = self.get_message_type(data.get("method", "")) if "jsonrpc" in data else None
        if kind is None or "id" not in data:
            return super().structure_message(data)
        try:
            return self._converter.structure(data, kind)
        except Exception as error:
            return self._refuse(data["id"], JsonRpcInvalidParams(
                f"invalid {data['method']} request: " + " ".join(_reasons(error))))

    def handle_message(self, message):
        if isinstance(message, _Answered):
            return
        if isinstance(message, dict):       # an object without "jsonrpc"
            if "id" in message:
                self._refuse(message["id"], JsonRpcInvalidRequest(
                    "invalid message: it has no 'jsonrpc' version"))
            return
        if (self._shutdown and getattr(message, "method", types.EXIT) != types.EXIT
                and hasattr(message, "id")):
            self._refuse(message.id, JsonRpcInvalidRequest(
                f"{message.method}: the server is shut down (only 'exit' is accepted)"))
            return
        super().handle_message(message)

    def refuse_unreadable(self, error: BaseException) -> None:
        """Answer a message that is not JSON with a parse error (it has no id to answer)."""
        reply = JsonRpcParseError(f"the message is not JSON: {error}")
        self._send_data({"jsonrpc": self.VERSION, "id": None,
                         "error": {"code": reply.code, "message": reply.message}})

    def _refuse(self, msg_id, error) -> _Answered:
        self._send_response(msg_id, error=error.to_response_error())
        return _Answered()

    def _to_server(self, method: str, params):
        if (handler := self.fm.features.get(method)) is not None:
            yield handler, (params,), None

    @lsp_method(types.TEXT_DOCUMENT_DID_OPEN)
    def lsp_text_document__did_open(self, params: types.DidOpenTextDocumentParams):
        yield from self._to_server(types.TEXT_DOCUMENT_DID_OPEN, params)

    @lsp_method(types.TEXT_DOCUMENT_DID_CHANGE)
    def lsp_text_document__did_change(self, params: types.DidChangeTextDocumentParams):
        yield from self._to_server(types.TEXT_DOCUMENT_DID_CHANGE, params)

    @lsp_method(types.TEXT_DOCUMENT_DID_CLOSE)
    def lsp_text_document__did_close(self, params: types.DidCloseTextDocumentParams):
        yield from self._to_server(types.TEXT_DOCUMENT_DID_CLOSE, params)


class Refusals(logging.Filter):
    """Drops pygls's log record (a traceback) of a request answered by an error on
    purpose (a rename to a name already taken, a position outside its document, a
    request cancelled): the client gets the reason as the answer."""

    def filter(self, record: logging.LogRecord) -> bool:
        error = record.exc_info[1] if record.exc_info else None
        return not isinstance(error, (JsonRpcInvalidParams, JsonRpcRequestCancelled))
