"""The JSON-RPC side of the server: pygls's protocol, with a request whose parameters
are not valid (a negative or fractional position, one past 2^31 - 1, a missing
field), a message that is not JSON-RPC 2.0 (:mod:`.envelope`), and a request after
``shutdown`` answered by an error that says what is wrong instead of being dropped or
shown to the user, and the documents' texts left to the server (pygls's own copies,
rebuilt line by line at each change, are not kept)."""

from __future__ import annotations

import logging

from lsprotocol import types
from pygls.exceptions import (JsonRpcInvalidParams, JsonRpcInvalidRequest,
                              JsonRpcParseError, JsonRpcRequestCancelled)
from pygls.protocol import LanguageServerProtocol, default_converter, lsp_method

from . import envelope


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


def _notification_with_id(message: dict) -> bool:
    """Whether ``message`` names a notification of the protocol (but ``exit``, honoured
    however it comes) and carries an id, as a request would: it must be answered, and
    the server has no answer to give."""
    method = message.get("method")
    return "id" in message and method != types.EXIT \
        and types.METHOD_TO_TYPES.get(method, (None, True))[1] is None


class MissionProtocol(LanguageServerProtocol):
    """pygls's language server protocol; a malformed message gets an error reply."""

    def structure_message(self, data: dict):
        """Every object of a message as it is: the message is read whole, once decoded
        (:meth:`handle_message`), so that no object inside it is read as a message."""
        return data

    def handle_message(self, message):
        reason = envelope.invalid(message)
        if reason is not None:
            self._refuse(envelope.answer_id(message),
                         JsonRpcInvalidRequest(f"invalid message: {reason}"))
            return
        if _notification_with_id(message):
            self._refuse(message["id"], JsonRpcInvalidRequest(
                f"{message['method']} is a notification: it is sent without an id, and "
                "gets no reply"))
            return
        structured = self._structured(message)
        if structured is None:
            return
        if self._shutdown and "id" in message and message.get("method", types.EXIT) \
                != types.EXIT:
            self._refuse(message["id"], JsonRpcInvalidRequest(
                f"{message['method']}: the server is shut down (only 'exit' is accepted)"))
            return
        super().handle_message(structured)

    def _structured(self, data: dict):
        """``data`` as pygls's type of its message; ``None`` when its parameters (or
        result) do not fit that type: a request gets an "invalid params" error, anything
        else is ignored, saying why in the editor's log."""
        kind = self.get_message_type(data["method"]) if "method" in data else None
        try:
            if kind is None:
                return super().structure_message(data)
            return self._converter.structure(data, kind)
        except Exception as error:
            reason = " ".join(dict.fromkeys(_reasons(error.__cause__ or error)))
        if "method" in data and "id" in data:
            self._refuse(data["id"], JsonRpcInvalidParams(
                f"invalid {data['method']} request: {reason}"))
        else:
            self.notify(types.WINDOW_LOG_MESSAGE, types.LogMessageParams(
                types.MessageType.Error,
                f"{data.get('method', 'a response')} ignored: {reason}"))
        return None

    def refuse_unreadable(self, error: BaseException) -> None:
        """Answer a message that is not JSON with a parse error (it has no id to answer)."""
        self._refuse(None, JsonRpcParseError(f"the message is not JSON: {error}"))

    def _refuse(self, msg_id, error) -> None:
        """An error reply to ``msg_id`` (``None``: an id that cannot be read, sent as
        null)."""
        self._send_data({"jsonrpc": envelope.VERSION, "id": msg_id,
                         "error": {"code": error.code, "message": error.message}})

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
