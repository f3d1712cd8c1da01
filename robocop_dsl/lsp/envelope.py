"""The JSON-RPC 2.0 envelope of a message: what makes a decoded JSON value a request, a
notification or a response, and the id that an error about one that is none of them
is sent with (JSON-RPC 2.0, section 5: null when the id cannot be read)."""

from __future__ import annotations

import json

VERSION = "2.0"
_KINDS = {list: "an array (the protocol has no batches)", str: "a string",
          bool: "a boolean", int: "a number", float: "a number", type(None): "null"}


def _is_id(value) -> bool:
    """Whether ``value`` can be a request's id: an integer or a string."""
    return isinstance(value, (int, str)) and not isinstance(value, bool)


def _is_response(message: dict) -> bool:
    return "method" not in message and ("result" in message or "error" in message)


def answer_id(message) -> int | str | None:
    """The id an error about ``message`` is sent with: a request's own when it can be
    read, else null (a response's id is the server's: answering with it would answer
    one of the client's own requests)."""
    if not isinstance(message, dict) or _is_response(message):
        return None
    msg_id = message.get("id")
    return msg_id if _is_id(msg_id) else None


def invalid(message) -> str | None:
    """Why ``message`` is not a JSON-RPC 2.0 request, notification or response, or
    ``None`` when it is one."""
    if not isinstance(message, dict):
        return f"it is {_KINDS[type(message)]}, not an object"
    if message.get("jsonrpc") != VERSION:
        return f"its \"jsonrpc\" is {_shown(message, 'jsonrpc')}, not \"{VERSION}\""
    if "method" in message and not isinstance(message["method"], str):
        return f"its method is {_shown(message, 'method')}, not a string"
    if not any(key in message for key in ("method", "result", "error")):
        return "it has no 'method', 'result' or 'error'"
    if "id" in message and not _is_id(message["id"]) and not (
            _is_response(message) and message["id"] is None):
        return f"its id is {_shown(message, 'id')}, not an integer or a string"
    return None


def _shown(message: dict, key: str) -> str:
    """The JSON of ``message[key]``; ``missing`` when there is none."""
    return json.dumps(message[key]) if key in message else "missing"
