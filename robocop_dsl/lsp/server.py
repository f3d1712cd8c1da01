"""The language server for ``.mission`` files (Language Server Protocol over stdio, on
pygls): diagnostics as you type with their quick fixes, completion, signature help,
hover, definition, references, highlights, rename, outline, folding, formatting and
semantic highlighting.

The event loop's thread only reads messages and answers at once: requests are worked
out on request threads and checks on the checking thread (:mod:`.scheduler`), so that
an edit, a cancellation or ``exit`` is always read. Positions are in the encoding
agreed at initialization (:class:`~.positions.Encoding`)."""

from __future__ import annotations

import asyncio
import json
import logging
import os
import stat
import sys
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import BinaryIO, Callable

from lsprotocol import types
from pygls.exceptions import JsonRpcInvalidParams
from pygls.io_ import StdoutWriter, run_async
from pygls.lsp.server import LanguageServer

from .. import __version__
from ..check import Cancelled
from ..sources import editor_lines
from . import (checking, completion, diagnostics, folding, formatting, hover, navigation,
               parent, semantic_tokens, signatures, symbols)
from .changes import Texts, reversed_range
from .positions import SPELLINGS, Encoding, path_to_uri, unknown_document, uri_to_path
from .project import COLLECTOR, Project
from .protocol import MissionProtocol, Refusals, converter
from .scheduler import Checks
from .worlds import WorldStore

REQUEST_THREADS = 2
MAX_HEADER = 1 << 16
"""The longest header line read [bytes]."""


class MissionServer(LanguageServer):
    """A pygls server holding the :class:`Project` of the editor's workspace."""

    def __init__(self):
        super().__init__("robocop-mission", __version__, protocol_cls=MissionProtocol,
                         converter_factory=converter)
        self.project = Project(WorldStore(on_load=self.world_loaded))
        self.checks = Checks(self.project.open, self.check, self.publish, self.open_importers,
                             self.check_failed)
        self.shut_down = False
        self.texts = Texts(Encoding(None, self.project.source).units)
        self._requests = ThreadPoolExecutor(REQUEST_THREADS, thread_name_prefix="request")
        self._loop: asyncio.AbstractEventLoop | None = None

    def start_io(self, stdin: BinaryIO | None = None, stdout: BinaryIO | None = None):
        """Serve on ``stdin`` and ``stdout``. A pipe is read by the event loop itself
        (pygls reads each line of a message on a worker thread; a burst of edits then
        queues behind those hand-overs); anything else, pygls's way."""
        stdin = stdin or sys.stdin.buffer
        if not stat.S_ISFIFO(os.fstat(stdin.fileno()).st_mode):
            super().start_io(stdin, stdout)
            return
        self._stop_event = threading.Event()
        self.protocol.set_writer(StdoutWriter(stdout or sys.stdout.buffer))
        try:
            asyncio.run(self._serve(stdin))
        except BrokenPipeError:
            logging.getLogger(__name__).error("the editor closed the connection")
        finally:
            self.shutdown()

    async def _serve(self, stdin: BinaryIO) -> None:
        loop = asyncio.get_running_loop()
        reader = asyncio.StreamReader(limit=MAX_HEADER, loop=loop)
        await loop.connect_read_pipe(lambda: asyncio.StreamReaderProtocol(reader), stdin)
        await run_async(stop_event=self._stop_event, reader=reader, protocol=self.protocol,
                        error_handler=self.report_server_error)

    def report_server_error(self, error: Exception, source) -> None:
        """A message that is not JSON gets a parse error reply; anything else, pygls's
        report to the user."""
        if isinstance(error, json.JSONDecodeError):
            self.protocol.refuse_unreadable(error)
        else:
            super().report_server_error(error, source)

    # ---- threads ----
    async def answer(self, work: Callable, *args):
        """``work(*args)`` worked out on a request thread, cyclic garbage collection
        paused meanwhile (see :data:`~.project.COLLECTOR`)."""
        return await asyncio.get_running_loop().run_in_executor(self._requests, _paused,
                                                                work, *args)

    def on_loop(self, call: Callable, *args) -> None:
        """``call(*args)`` on the event loop's thread (where messages are sent)."""
        if self._loop is None:
            call(*args)
        else:
            self._loop.call_soon_threadsafe(call, *args)

    def encoding(self) -> Encoding:
        return Encoding(self.workspace.position_encoding, self.project.source)

    def document(self, params) -> Path:
        """The path of a request's document (refused when it is unknown)."""
        path = uri_to_path(params.text_document.uri)
        if self.project.text(path) is None:
            raise JsonRpcInvalidParams(unknown_document(path))
        return path

    def place(self, params) -> tuple[Encoding, Path, int, int]:
        """The encoding, and the document, 0-based line and character column of a
        request's position (refused when it is not in its document)."""
        encoding = self.encoding()
        path = uri_to_path(params.text_document.uri)
        return (encoding, path, *encoding.decode(path, params.position))

    # ---- checks ----
    def world_loaded(self, path: Path) -> None:
        self.on_loop(self.window_log_message,
                     types.LogMessageParams(types.MessageType.Info, f"loaded world {path}"))

    def check(self, path: Path, text: str, stale: Callable[[], bool]):
        """On the checking thread: the protocol diagnostics of ``text`` as the content
        of ``path``, ``None`` when ``stale()`` turns true first."""
        try:
            parsed = self.project.parse(path, text, stale)
        except Cancelled:
            return None
        found = None if stale() else checking.check(self.project, parsed, stale)
        if found is None:
            return None
        encoding = self.encoding()
        return [encoding.diagnostic(path, diagnostics.convert(self.project, parsed, d))
                for d in found]

    def publish(self, path: Path, found: list[types.Diagnostic], version: int | None) -> None:
        self.text_document_publish_diagnostics(types.PublishDiagnosticsParams(
            uri=path_to_uri(path), diagnostics=found, version=version))

    def check_failed(self, path: Path, error: BaseException) -> None:
        self.window_log_message(types.LogMessageParams(
            types.MessageType.Error, f"checking {path} failed: {type(error).__name__}: {error}"))

    def open_importers(self, path: Path) -> list[Path]:
        return self.project.importers(path, list(self.project.open))

    def recheck_open(self) -> None:
        for path in list(self.project.open):
            self.checks.request(path, 0, edited=False)


def _paused(work: Callable, *args):
    with COLLECTOR.paused():
        return work(*args)


def _symbols(encoding: Encoding, path: Path, found: list[types.DocumentSymbol]):
    for symbol in found:
        symbol.range = encoding.range(path, symbol.range)
        symbol.selection_range = encoding.range(path, symbol.selection_range)
        _symbols(encoding, path, symbol.children or [])
    return found


def build_server() -> MissionServer:
    """A server with every feature registered."""
    server = MissionServer()
    project = server.project
    logging.getLogger("pygls.protocol.json_rpc").addFilter(Refusals())

    @server.feature(types.INITIALIZE)
    def initialize(ls: MissionServer, params: types.InitializeParams):
        parent.watch(params.process_id)

    @server.feature(types.INITIALIZED)
    def initialized(ls: MissionServer, params: types.InitializedParams):
        ls._loop = asyncio.get_running_loop()
        ls.texts = Texts(ls.encoding().units)
        folders = [f.uri for f in ls.workspace.folders.values()]
        if not folders and ls.workspace.root_uri:
            folders = [ls.workspace.root_uri]
        project.roots = SPELLINGS.folders(folders)

    @server.feature(types.TEXT_DOCUMENT_DID_OPEN)
    def did_open(ls: MissionServer, params: types.DidOpenTextDocumentParams):
        path = SPELLINGS.opened(params.text_document.uri)
        project.open[path] = editor_lines(params.text_document.text)
        ls.checks.versions[path] = params.text_document.version
        ls.checks.request(path, 0)

    @server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
    def did_change(ls: MissionServer, params: types.DidChangeTextDocumentParams):
        path = uri_to_path(params.text_document.uri)
        text = project.open.get(path)
        if text is None:        # a notification has no answer: the reason goes to the log
            ls.window_log_message(types.LogMessageParams(
                types.MessageType.Warning, f"change to {path} ignored: it is not open"))
            return
        for change in params.content_changes:
            if reversed_range(change):
                start, end = change.range.start, change.range.end
                ls.window_log_message(types.LogMessageParams(
                    types.MessageType.Warning,
                    f"change to {path}: its range ends ({end.line}:{end.character}) before "
                    f"it starts ({start.line}:{start.character}); the text between them "
                    "is replaced"))
            text = editor_lines(ls.texts.apply(text, change))
        project.open[path] = text
        ls.checks.versions[path] = params.text_document.version
        ls.checks.request(path)

    @server.feature(types.TEXT_DOCUMENT_DID_SAVE)
    def did_save(ls: MissionServer, params: types.DidSaveTextDocumentParams):
        ls.recheck_open()

    @server.feature(types.WORKSPACE_DID_CHANGE_WATCHED_FILES)
    def files_changed(ls: MissionServer, params: types.DidChangeWatchedFilesParams):
        ls.recheck_open()

    @server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
    def did_close(ls: MissionServer, params: types.DidCloseTextDocumentParams):
        path = uri_to_path(params.text_document.uri)
        project.open.pop(path, None)
        project.forget(path)
        SPELLINGS.closed(path)
        ls.text_document_publish_diagnostics(
            types.PublishDiagnosticsParams(uri=params.text_document.uri, diagnostics=[]))
        ls.recheck_open()

    @server.feature(types.SHUTDOWN)
    def shutdown(ls: MissionServer, params):
        ls.shut_down = True
        ls.checks.stop()

    @server.feature(types.EXIT)
    def exit_now(ls: MissionServer, params):
        """End the process at once: a check or a request still being worked out on its
        thread is dropped (nothing is written after the last answer)."""
        os._exit(0 if ls.shut_down else 1)

    @server.feature(types.TEXT_DOCUMENT_COMPLETION,
                    types.CompletionOptions(trigger_characters=[":", "(", ".", " ", ",", "=",
                                                                "{"]))
    async def complete(ls: MissionServer, params: types.CompletionParams):
        def work():
            encoding, path, line, character = ls.place(params)
            items = completion.complete(project, path, line, character)
            for item in items:
                item.text_edit = encoding.edit(path, item.text_edit)
            return types.CompletionList(is_incomplete=False, items=items)
        return await ls.answer(work)

    @server.feature(types.TEXT_DOCUMENT_SIGNATURE_HELP,
                    types.SignatureHelpOptions(trigger_characters=["(", ","],
                                               retrigger_characters=[" ", "="]))
    async def signature(ls: MissionServer, params: types.SignatureHelpParams):
        def work():
            _, path, line, character = ls.place(params)
            return signatures.signature_help(project, path, line, character)
        return await ls.answer(work)

    @server.feature(types.TEXT_DOCUMENT_HOVER)
    async def on_hover(ls: MissionServer, params: types.HoverParams):
        def work():
            encoding, path, line, character = ls.place(params)
            found = hover.hover(project, path, line + 1, character + 1)
            if found is not None and found.range is not None:
                found.range = encoding.range(path, found.range)
            return found
        return await ls.answer(work)

    @server.feature(types.TEXT_DOCUMENT_DEFINITION)
    async def definition(ls: MissionServer, params: types.DefinitionParams):
        def work():
            encoding, path, line, character = ls.place(params)
            found = navigation.definition(project, path, line + 1, character + 1)
            return [encoding.location(f) for f in found]
        return await ls.answer(work)

    @server.feature(types.TEXT_DOCUMENT_REFERENCES)
    async def references(ls: MissionServer, params: types.ReferenceParams):
        def work():
            encoding, path, line, character = ls.place(params)
            _, _, target = navigation.target_at(project, path, line + 1, character + 1)
            if target is None:
                return []
            found = navigation.references(project, target, params.context.include_declaration)
            return [encoding.location(f) for f in found]
        return await ls.answer(work)

    @server.feature(types.TEXT_DOCUMENT_DOCUMENT_HIGHLIGHT)
    async def highlight(ls: MissionServer, params: types.DocumentHighlightParams):
        def work():
            encoding, path, line, character = ls.place(params)
            found = navigation.highlights(project, path, line + 1, character + 1)
            for place in found:
                place.range = encoding.range(path, place.range)
            return found
        return await ls.answer(work)

    @server.feature(types.TEXT_DOCUMENT_PREPARE_RENAME)
    async def prepare_rename(ls: MissionServer, params: types.PrepareRenameParams):
        def work():
            encoding, path, line, character = ls.place(params)
            found = navigation.prepare_rename(project, path, line + 1, character + 1)
            return encoding.range(path, found) if found is not None else None
        return await ls.answer(work)

    @server.feature(types.TEXT_DOCUMENT_RENAME)
    async def rename(ls: MissionServer, params: types.RenameParams):
        def work():
            encoding, path, line, character = ls.place(params)
            found = navigation.rename(project, path, line + 1, character + 1, params.new_name)
            return encoding.workspace_edit(found) if found is not None else None
        return await ls.answer(work)

    @server.feature(types.TEXT_DOCUMENT_CODE_ACTION,
                    types.CodeActionOptions(code_action_kinds=[types.CodeActionKind.QuickFix]))
    async def code_action(ls: MissionServer, params: types.CodeActionParams):
        def work():
            encoding, path = ls.encoding(), ls.document(params)
            for end in (params.range.start, params.range.end):
                encoding.decode(path, end)
            return diagnostics.code_actions(params.context.diagnostics, encoding)
        return await ls.answer(work)

    @server.feature(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    async def outline(ls: MissionServer, params: types.DocumentSymbolParams):
        def work():
            path = ls.document(params)
            return _symbols(ls.encoding(), path,
                            symbols.document_symbols(project.parsed(path).tree))
        return await ls.answer(work)

    @server.feature(types.TEXT_DOCUMENT_FOLDING_RANGE)
    async def fold(ls: MissionServer, params: types.FoldingRangeParams):
        def work():
            return folding.folding_ranges(project.text(ls.document(params)))
        return await ls.answer(work)

    @server.feature(types.TEXT_DOCUMENT_FORMATTING)
    async def format_document(ls: MissionServer, params: types.DocumentFormattingParams):
        def work():
            path = ls.document(params)
            found = formatting.format_document(project.parsed(path))
            return [ls.encoding().edit(path, e) for e in found] if found is not None else None
        return await ls.answer(work)

    @server.feature(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL, semantic_tokens.LEGEND)
    async def tokens(ls: MissionServer, params: types.SemanticTokensParams):
        def work():
            path, encoding = ls.document(params), ls.encoding()
            return semantic_tokens.semantic_tokens(
                project, project.parsed(path),
                lambda line, character: encoding.column(path, line, character))
        return await ls.answer(work)

    return server
