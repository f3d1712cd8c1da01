"""``robocop-mission lsp``: the language server for editors, over stdin and stdout.

Editors' language clients name the transport they want on the command line:
``--stdio`` is served; ``--socket=N``, ``--pipe=NAME`` and ``--node-ipc`` are refused
(exit code 2, saying so); ``--clientProcessId=N`` names the editor's process: the server exits once it is gone.
"""

from __future__ import annotations

import argparse
import os
import sys

_OTHER_TRANSPORTS = (("--socket", "PORT", "a TCP socket"), ("--pipe", "NAME", "a named pipe"))


class _Refused(argparse.Action):
    """A transport this server does not speak: a usage error that says which it does."""

    def __call__(self, parser, namespace, values, option_string=None):
        parser.error(f"{option_string}: this server speaks the Language Server Protocol "
                     "over stdio only (use --stdio, or no transport option)")


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "lsp", help="run the language server for editors (stdio)",
        description="Serve the Language Server Protocol on stdin/stdout: diagnostics as "
                    "you type, quick fixes, completion, signature help, hover, definition, "
                    "references, rename, outline, folding, formatting and semantic "
                    "highlighting of .mission files.")
    parser.add_argument("--stdio", action="store_true",
                        help="serve over stdin and stdout (the default and only transport)")
    for option, metavar, what in _OTHER_TRANSPORTS:
        parser.add_argument(option, metavar=metavar, action=_Refused,
                            help=f"refused: {what} is not served")
    parser.add_argument("--node-ipc", nargs=0, action=_Refused,
                        help="refused: Node's IPC channel is not served")
    parser.add_argument("--clientProcessId", metavar="PID", type=int,
                        help="the editor's process id: exit once it has ended")
    parser.set_defaults(command=run)


def run(args) -> int:
    """Serve until the editor sends ``exit`` (the process ends at once) or closes the
    connection. The server writes to a copy of standard output, which it closes on
    exit; the command's own stays usable."""
    from ..lsp import parent
    from ..lsp.server import build_server

    parent.watch(args.clientProcessId)
    with os.fdopen(os.dup(sys.stdout.fileno()), "wb") as output:
        build_server().start_io(sys.stdin.buffer, output)
    return 0
