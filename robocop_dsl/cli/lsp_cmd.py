"""``robocop-mission lsp``: the language server for editors, over stdin and stdout."""

from __future__ import annotations

import os
import sys


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "lsp", help="run the language server for editors (stdio)",
        description="Serve the Language Server Protocol on stdin/stdout: diagnostics as "
                    "you type, completion, hover, definition, references, rename, "
                    "outline, formatting and semantic highlighting of .mission files.")
    parser.set_defaults(command=run)


def run(args) -> int:
    """Serve until the editor closes the connection. The server writes to a copy of
    standard output, which it closes on exit; the command's own stays usable."""
    from ..lsp.server import build_server

    with os.fdopen(os.dup(sys.stdout.fileno()), "wb") as output:
        build_server().start_io(sys.stdin.buffer, output)
    return 0
