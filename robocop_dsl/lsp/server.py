"""The language server for ``.mission`` files (Language Server Protocol over stdio,
on pygls): diagnostics as you type, completion, hover, definition, references,
rename, outline, formatting and semantic highlighting."""

from __future__ import annotations

import logging
from pathlib import Path

from lsprotocol import types
from pygls.exceptions import JsonRpcInvalidParams
from pygls.lsp.server import LanguageServer

from .. import __version__
from . import completion, diagnostics, formatting, hover, navigation, semantic_tokens, symbols
from .positions import one_based, path_to_uri, uri_to_path
from .project import Project
from .worlds import WorldStore


class Refusals(logging.Filter):
    """Drops pygls's log record (a traceback) of a request refused on purpose, such as
    a rename to a name already taken: the client gets the reason as the answer."""

    def filter(self, record: logging.LogRecord) -> bool:
        error = record.exc_info[1] if record.exc_info else None
        return not isinstance(error, JsonRpcInvalidParams)


REFUSALS = Refusals()


class MissionServer(LanguageServer):
    """A pygls server holding the :class:`Project` of the editor's workspace."""

    def __init__(self):
        super().__init__("robocop-mission", __version__)
        self.project = Project(WorldStore(on_load=self.world_loaded))

    def world_loaded(self, path: Path) -> None:
        self.window_log_message(types.LogMessageParams(types.MessageType.Info,
                                                       f"loaded world {path}"))

    def publish(self, path: Path) -> None:
        """Check ``path``'s current text and send its diagnostics."""
        found = diagnostics.diagnostics(self.project, path)
        self.text_document_publish_diagnostics(
            types.PublishDiagnosticsParams(uri=path_to_uri(path), diagnostics=found))

    def recheck_open(self) -> None:
        for path in list(self.project.open):
            self.publish(path)


def build_server() -> MissionServer:
    """A server with every feature registered."""
    server = MissionServer()
    project = server.project
    logging.getLogger("pygls.protocol.json_rpc").addFilter(REFUSALS)

    @server.feature(types.INITIALIZED)
    def initialized(ls: MissionServer, params: types.InitializedParams):
        folders = ls.workspace.folders.values()
        project.roots = [uri_to_path(f.uri) for f in folders]
        if not project.roots and ls.workspace.root_path:
            project.roots = [Path(ls.workspace.root_path).resolve()]

    @server.feature(types.TEXT_DOCUMENT_DID_OPEN)
    def did_open(ls: MissionServer, params: types.DidOpenTextDocumentParams):
        path = uri_to_path(params.text_document.uri)
        project.open[path] = params.text_document.text
        ls.publish(path)

    @server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
    def did_change(ls: MissionServer, params: types.DidChangeTextDocumentParams):
        document = ls.workspace.get_text_document(params.text_document.uri)
        path = uri_to_path(params.text_document.uri)
        project.open[path] = document.source
        ls.publish(path)

    @server.feature(types.TEXT_DOCUMENT_DID_SAVE)
    def did_save(ls: MissionServer, params: types.DidSaveTextDocumentParams):
        ls.recheck_open()

    @server.feature(types.WORKSPACE_DID_CHANGE_WATCHED_FILES)
    def files_changed(ls: MissionServer, params: types.DidChangeWatchedFilesParams):
        ls.recheck_open()

    @server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
    def did_close(ls: MissionServer, params: types.DidCloseTextDocumentParams):
        project.open.pop(uri_to_path(params.text_document.uri), None)
        ls.text_document_publish_diagnostics(
            types.PublishDiagnosticsParams(uri=params.text_document.uri, diagnostics=[]))

    @server.feature(types.TEXT_DOCUMENT_COMPLETION,
                    types.CompletionOptions(trigger_characters=[":", "(", ".", " ", ",", "="]))
    def complete(ls: MissionServer, params: types.CompletionParams):
        position = params.position
        items = completion.complete(project, uri_to_path(params.text_document.uri),
                                    position.line, position.character)
        return types.CompletionList(is_incomplete=False, items=items)

    @server.feature(types.TEXT_DOCUMENT_HOVER)
    def on_hover(ls: MissionServer, params: types.HoverParams):
        return hover.hover(project, uri_to_path(params.text_document.uri),
                           *one_based(params.position))

    @server.feature(types.TEXT_DOCUMENT_DEFINITION)
    def definition(ls: MissionServer, params: types.DefinitionParams):
        return navigation.definition(project, uri_to_path(params.text_document.uri),
                                     *one_based(params.position))

    @server.feature(types.TEXT_DOCUMENT_REFERENCES)
    def references(ls: MissionServer, params: types.ReferenceParams):
        _, _, target = navigation.target_at(project, uri_to_path(params.text_document.uri),
                                            *one_based(params.position))
        if target is None:
            return []
        return navigation.references(project, target, params.context.include_declaration)

    @server.feature(types.TEXT_DOCUMENT_PREPARE_RENAME)
    def prepare_rename(ls: MissionServer, params: types.PrepareRenameParams):
        return navigation.prepare_rename(project, uri_to_path(params.text_document.uri),
                                         *one_based(params.position))

    @server.feature(types.TEXT_DOCUMENT_RENAME)
    def rename(ls: MissionServer, params: types.RenameParams):
        return navigation.rename(project, uri_to_path(params.text_document.uri),
                                 *one_based(params.position), params.new_name)

    @server.feature(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    def outline(ls: MissionServer, params: types.DocumentSymbolParams):
        parsed = project.parsed(uri_to_path(params.text_document.uri))
        return symbols.document_symbols(parsed.tree) if parsed else []

    @server.feature(types.TEXT_DOCUMENT_FORMATTING)
    def format_document(ls: MissionServer, params: types.DocumentFormattingParams):
        parsed = project.parsed(uri_to_path(params.text_document.uri))
        return formatting.format_document(parsed) if parsed else None

    @server.feature(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL, semantic_tokens.LEGEND)
    def tokens(ls: MissionServer, params: types.SemanticTokensParams):
        parsed = project.parsed(uri_to_path(params.text_document.uri))
        return semantic_tokens.semantic_tokens(project, parsed) if parsed else None

    return server
