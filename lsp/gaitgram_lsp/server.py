"""The gaitgram language server: registers features, nothing more.

Each handler fetches the document's snapshot (``documents.py``), calls one pure function
(``features/``) and returns what it gives. Requests about a document that changed while
they waited get LSP's ContentModified, so the client asks again.
"""

from __future__ import annotations

import argparse
import asyncio
import contextvars
import functools
import json
import logging
import sys
import threading
from collections.abc import Awaitable, Callable
from functools import cache
from typing import BinaryIO

import attrs
import cattrs
from cattrs.errors import ClassValidationError
from lsprotocol import types
from pygls.capabilities import get_capability
from pygls.exceptions import (
    JsonRpcContentModified,
    JsonRpcInvalidParams,
    JsonRpcInvalidRequest,
    JsonRpcServerNotInitialized,
)
from pygls.io_ import StdoutWriter
from pygls.lsp.server import LanguageServer
from pygls.protocol import JsonRPCNotification, JsonRPCProtocol, LanguageServerProtocol, default_converter
from pygls.protocol.json_rpc import RPCMessage
from pygls.protocol.language_server import lsp_method

from gaitgram import __version__
from gaitgram_lsp import framing
from gaitgram_lsp.documents import Documents, Snapshot, workspace_grammars
from gaitgram_lsp.features import (
    code_actions,
    completion,
    folding,
    formatting,
    hover,
    inlay_hints,
    navigation,
    semantic_tokens,
)
from gaitgram_lsp.positions import column, position_problems

logger = logging.getLogger(__name__)

#: Seconds the analysis thread may hold the GIL while the event loop waits for it.
SWITCH_INTERVAL = 0.0005


def strict_converter() -> cattrs.Converter:
    """pygls's converter, with positions checked: out of range or not integers is InvalidParams."""
    converter = default_converter()

    def position(value: object, _: type) -> types.Position:
        if problems := position_problems(value):
            raise ClassValidationError(problems[0], [ValueError(p) for p in problems], types.Position)
        return types.Position(line=value["line"], character=value["character"])  # type: ignore[index]

    converter.register_structure_hook(types.Position, position)
    return converter


def _leaves(error: BaseException) -> list[str]:
    """The innermost messages of cattrs's nested exception groups: what was actually wrong."""
    if isinstance(error, BaseExceptionGroup):
        return [leaf for inner in error.exceptions for leaf in _leaves(inner)]
    return [str(error)]


#: What :meth:`GaitgramProtocol.structure_message` gives for a message it answered itself.
_ANSWERED = JsonRPCNotification(method="$/gaitgram/answered", jsonrpc="2.0", params=None)


@cache
def _is_notification(method: str) -> bool:
    """Whether LSP defines ``method`` as a notification (a message without an id)."""
    message_type = types.METHOD_TO_TYPES.get(method, (None,))[0]
    return message_type is not None and "id" not in attrs.fields_dict(message_type)


def _invalid_request(data: dict) -> str | None:
    """Why a message with an id is not a request or a response the server can take, or None.

    pygls reads such messages as notifications (or drops them) and never answers, so the client
    waits forever for the answer to its id."""
    if data.get("jsonrpc") != JsonRPCProtocol.VERSION:
        return f'"jsonrpc" must be "2.0", not {json.dumps(data.get("jsonrpc"))}'
    if not _is_id(data["id"]):
        return f"the id must be a number or a string, not {json.dumps(data['id'])}"
    if "method" not in data:
        if "result" in data or "error" in data:
            return None  # a response to a request of the server's
        return "a message with an id needs a method (a request), or a result or an error (a response)"
    method = data["method"]
    if not isinstance(method, str):
        return f"the method must be a string, not {json.dumps(method)}"
    if _is_notification(method):
        return f"{method} is a notification, which is sent without an id"
    return None


#: The fields of pygls's message protocols (``RPCRequest``, ``RPCNotification``, ``RPCResponse``).
_REQUEST = ("id", "method", "jsonrpc", "params")
_NOTIFICATION = ("method", "jsonrpc", "params")
_RESPONSE = ("id", "jsonrpc", "result")


def _is(message: object, fields: tuple[str, ...]) -> bool:
    """Whether ``message`` has ``fields``: what ``isinstance`` against pygls's protocol asks."""
    return all(hasattr(message, name) for name in fields)


def _is_id(value: object) -> bool:
    return isinstance(value, int | str) and not isinstance(value, bool)


class GaitgramProtocol(LanguageServerProtocol):
    """pygls's protocol, answering every request as JSON-RPC and the LSP specification say:
    invalid ones and those after ``shutdown`` with an error, never with silence."""

    def structure_message(self, data: dict):  # type: ignore[no-untyped-def]  # pygls's signature
        """As pygls's, but a message with an id that is not a valid request gets InvalidRequest,
        and a request whose parameters do not read gets InvalidParams (pygls logs both and
        never answers, so the client waits forever). Called for every JSON object of a
        message; only a whole message has ``jsonrpc``."""
        if "id" in data and "jsonrpc" in data and (reason := _invalid_request(data)) is not None:
            self._refuse(data["id"], JsonRpcInvalidRequest.CODE, f"invalid request: {reason}")
            return _ANSWERED
        try:
            return super().structure_message(data)
        except JsonRpcInvalidParams as error:
            if not ("id" in data and "method" in data):
                raise
            reason = "; ".join(_leaves(error.__cause__ or error))
            self._refuse(data["id"], error.code, f"invalid params for {data['method']}: {reason}")
            return _ANSWERED

    #: Whether ``initialize`` was received (the specification: once, and before anything else).
    initialize_received = False

    def handle_message(self, message: RPCMessage) -> None:
        """As pygls's, but the requests the specification refuses get their errors: before
        ``initialize`` ServerNotInitialized, a second ``initialize`` and any request after
        ``shutdown`` (another ``shutdown`` too) InvalidRequest. pygls drops some unanswered,
        and serves others before the server is set up. Notifications before ``initialize``
        are dropped, as the specification says, but for ``exit``."""
        if message is _ANSWERED:
            return
        if isinstance(message, dict):  # no "jsonrpc", so structure_message left it a plain object
            if "id" in message:
                reason = 'invalid request: a message needs "jsonrpc": "2.0"'
                self._refuse(message["id"], JsonRpcInvalidRequest.CODE, reason)
            return
        if _is(message, _REQUEST):
            method = message.method
            if self._shutdown:
                reason = f"the server is shut down: it takes only the exit notification now, not {method}"
                self._refuse(message.id, JsonRpcInvalidRequest.CODE, reason)
                return
            if method == types.INITIALIZE:
                if self.initialize_received:
                    self._refuse(message.id, JsonRpcInvalidRequest.CODE, "initialize may be sent only once")
                    return
                self.initialize_received = True
            elif not self.initialize_received:
                reason = f"the server is not initialized: send initialize before {method}"
                self._refuse(message.id, JsonRpcServerNotInitialized.CODE, reason)
                return
        elif _is(message, _NOTIFICATION) and not self.initialize_received and message.method != types.EXIT:
            return
        self._dispatch(message)

    def _dispatch(self, message: RPCMessage) -> None:
        """pygls's ``handle_message``, its message kinds told by their fields as its protocol
        classes tell them, without ``isinstance`` against those classes: a check of a
        runtime-checkable protocol costs a tenth of a millisecond, most of what a change
        notification costs the event loop when hundreds are queued."""
        if message.jsonrpc != JsonRPCProtocol.VERSION:
            logger.warning('Unknown message "%s"', message)
            return
        if self._shutdown and getattr(message, "method", "") != types.EXIT:
            logger.warning("Server shutting down. No more requests!")
            return
        context = contextvars.copy_context()  # each handler in its own context, as pygls runs it
        if _is(message, _REQUEST):
            context.run(self._handle_request, message.id, message.method, message.params)
        elif _is(message, _NOTIFICATION):
            context.run(self._handle_notification, message.method, message.params)
        elif _is(message, _RESPONSE):
            context.run(self._handle_response, message.id, message.result)
        else:
            context.run(self._handle_response, message.id, None, message.error)

    def _refuse(self, msg_id: object, code: int, message: str) -> None:
        """Answer ``msg_id`` with an error (JSON-RPC answers an id it cannot read with null)."""
        answered = msg_id if _is_id(msg_id) else None  # pygls's converter would leave out a null id
        self._send_data({"jsonrpc": "2.0", "id": answered, "error": {"code": code, "message": message}})

    @lsp_method(types.TEXT_DOCUMENT_DID_CHANGE)
    def lsp_text_document__did_change(self, params: types.DidChangeTextDocumentParams):
        """As pygls's, without updating pygls's own copy of the text: ``documents.py`` keeps
        the text, and pygls's copy splits lines at more characters than LSP does (form feed,
        U+2028, ...) and clamps the changes' positions to those lines, in place. Nothing
        reads ``workspace`` text documents."""
        if (handler := self.fm.features.get(types.TEXT_DOCUMENT_DID_CHANGE)) is not None:
            yield handler, (params,), None

    def notify_encoded(self, method: str, params_json: str) -> None:
        """Send a notification whose parameters are JSON already (ASCII, as ``json.dumps``
        makes it), framed as pygls frames its own messages. The server serves stdio and TCP,
        whose writers write at once."""
        if self.writer is None:
            return
        body = f'{{"jsonrpc":"2.0","method":{json.dumps(method)},"params":{params_json}}}'
        header = f"Content-Length: {len(body)}\r\nContent-Type: {self.CONTENT_TYPE}; charset={self.CHARSET}"
        self.writer.write(f"{header}\r\n\r\n{body}".encode(self.CHARSET))


class GaitgramServer(LanguageServer):
    def __init__(self) -> None:
        super().__init__(
            "gaitgram-lsp",
            __version__,
            text_document_sync_kind=types.TextDocumentSyncKind.Incremental,
            protocol_cls=GaitgramProtocol,
            converter_factory=strict_converter,
        )
        self.documents = Documents(self.publish)
        self.pull_diagnostics = False
        self.completion_client = completion.Client()
        self.markdown = True
        self.hierarchical_symbols = True
        #: The process's exit status: the LSP's for the exit notification (0 after shutdown,
        #: else 1), 0 if the client closed the connection.
        self.exit_status = 0

    def _start_io_async(self, stdin: BinaryIO | None = None, stdout: BinaryIO | None = None) -> None:
        """As pygls's, but messages are framed by :mod:`gaitgram_lsp.framing` (headers read as the
        base protocol says; a malformed message answered, never ending the stream), and stdin is
        read on the event loop as an asyncio pipe. pygls reads every header line and body with its
        own thread-pool call, three thread hand-offs per message (about 1 ms): 200 changes sent at
        once then held up a completion queued behind them for a fifth of a second. Stdin that is
        not a pipe (a regular file) is read in the thread pool."""
        self._stop_event = threading.Event()
        self.protocol.set_writer(StdoutWriter(stdout or sys.stdout.buffer))

        async def serve() -> None:
            source = stdin or sys.stdin.buffer
            loop = asyncio.get_running_loop()
            reader = asyncio.StreamReader()
            read: Callable[[int], Awaitable[bytes]] = reader.read
            try:
                await loop.connect_read_pipe(lambda: asyncio.StreamReaderProtocol(reader), source)
            except (ValueError, OSError):
                take = getattr(source, "read1", source.read)
                read = functools.partial(loop.run_in_executor, self.thread_pool, take)  # type: ignore[assignment]
            await self._serve(read)

        try:
            asyncio.run(serve())
        except BrokenPipeError:
            logger.error("Connection to the client is lost! Shutting down the server.")
        except SystemExit as stop:  # pygls's exit handler: its status is the process's
            self.exit_status = 0 if stop.code is None else stop.code if isinstance(stop.code, int) else 1
        except KeyboardInterrupt:
            pass
        finally:
            self.shutdown()

    async def _serve(self, read: Callable[[int], Awaitable[bytes]]) -> None:
        await framing.serve(
            read,
            self.protocol,
            self.protocol._refuse,
            self._stop_event.is_set,
            self.report_server_error,
        )

    def start_tcp(self, host: str, port: int) -> None:
        """As pygls's, with messages framed as on stdio (:mod:`gaitgram_lsp.framing`)."""
        self._stop_event = threading.Event()

        async def connection(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
            self.protocol.set_writer(writer)  # type: ignore[arg-type]  # pygls writes to it as pygls does
            await self._serve(reader.read)
            self.shutdown()

        async def listen() -> None:
            self._server = await asyncio.start_server(connection, host, port)
            async with self._server:
                await self._server.serve_forever()

        try:
            asyncio.run(listen())
        except asyncio.CancelledError:
            logger.debug("Server was cancelled")

    def configure(self, params: types.InitializeParams) -> None:
        """What the client can do, and the options it passes (``debounce`` in ms, ``defines``)."""
        capabilities = params.capabilities
        self.documents.encoding = self.workspace.position_encoding or types.PositionEncodingKind.Utf16
        self.pull_diagnostics = get_capability(capabilities, "text_document.diagnostic") is not None
        self.markdown = types.MarkupKind.Markdown in (
            get_capability(capabilities, "text_document.hover.content_format") or [types.MarkupKind.Markdown]
        )
        self.completion_client = completion.Client(
            snippets=bool(
                get_capability(capabilities, "text_document.completion.completion_item.snippet_support")
            ),
            markdown=types.MarkupKind.Markdown
            in (
                get_capability(capabilities, "text_document.completion.completion_item.documentation_format")
                or []
            ),
        )
        self.hierarchical_symbols = bool(
            get_capability(capabilities, "text_document.document_symbol.hierarchical_document_symbol_support")
        )
        options = params.initialization_options if isinstance(params.initialization_options, dict) else {}
        if isinstance(options.get("debounce"), int | float):
            self.documents.debounce = max(0.0, options["debounce"] / 1000)
        if isinstance(options.get("defines"), dict):
            self.documents.defines = {k: v for k, v in options["defines"].items() if isinstance(v, int)}

    def publish(self, snapshot: Snapshot) -> None:
        """Push diagnostics, unless the client pulls them (then pushing would show them twice)."""
        if not self.pull_diagnostics:
            self.protocol.notify_encoded(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS, snapshot.published_params)

    async def snapshot(self, uri: str, *, refused: bool = False) -> Snapshot | None:
        """The current text's snapshot; ContentModified if the text changes first. None for a
        text too large to analyse, unless ``refused`` (its diagnostics say why)."""
        snapshot = await self.documents.current(uri)
        if snapshot is None and self.documents.get(uri) is not None:
            raise JsonRpcContentModified()
        return None if snapshot is not None and snapshot.refused and not refused else snapshot


server = GaitgramServer()


@server.feature(types.INITIALIZE)
def initialize(ls: GaitgramServer, params: types.InitializeParams) -> None:
    ls.configure(params)


@server.feature(types.SHUTDOWN)
def shutdown(ls: GaitgramServer, params: None) -> None:
    ls.documents.shutdown()


@server.feature(types.TEXT_DOCUMENT_DID_OPEN)
def did_open(ls: GaitgramServer, params: types.DidOpenTextDocumentParams) -> None:
    document = params.text_document
    ls.documents.open(document.uri, document.text, document.version)


@server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
def did_change(ls: GaitgramServer, params: types.DidChangeTextDocumentParams) -> None:
    ls.documents.change(params.text_document.uri, params.text_document.version, params.content_changes)


@server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
def did_close(ls: GaitgramServer, params: types.DidCloseTextDocumentParams) -> None:
    ls.documents.close(params.text_document.uri)
    if not ls.pull_diagnostics:
        ls.text_document_publish_diagnostics(
            types.PublishDiagnosticsParams(uri=params.text_document.uri, diagnostics=[])
        )


@server.feature(
    types.TEXT_DOCUMENT_DIAGNOSTIC,
    types.DiagnosticOptions(
        identifier="gaitgram", inter_file_dependencies=False, workspace_diagnostics=False
    ),
)
async def diagnostic(
    ls: GaitgramServer, params: types.DocumentDiagnosticParams
) -> types.DocumentDiagnosticReport:
    snapshot = await ls.snapshot(params.text_document.uri, refused=True)
    if snapshot is None:
        return types.RelatedFullDocumentDiagnosticReport(items=[])
    if params.previous_result_id == snapshot.result_id:
        return types.RelatedUnchangedDocumentDiagnosticReport(result_id=snapshot.result_id)
    return types.RelatedFullDocumentDiagnosticReport(items=snapshot.diagnostics, result_id=snapshot.result_id)


@server.feature(
    types.TEXT_DOCUMENT_COMPLETION, types.CompletionOptions(trigger_characters=completion.TRIGGER_CHARACTERS)
)
async def complete(ls: GaitgramServer, params: types.CompletionParams) -> types.CompletionList | None:
    """From the last analysis and the current line: waits only for a document's first analysis."""
    document = ls.documents.get(params.text_document.uri)
    if document is None:
        return None
    if document.completion is None:
        await ls.documents.current(document.uri)
    if document.snapshot is not None and document.snapshot.refused:
        return None
    model = document.completion or completion.CompletionModel()
    line = document.line(params.position.line)
    return completion.complete(
        model,
        params.position.line,
        line,
        column(line, params.position.character, ls.documents.encoding),
        encoding=ls.documents.encoding,
        client=ls.completion_client,
        trigger=params.context.trigger_character if params.context else None,
    )


@server.feature(types.TEXT_DOCUMENT_HOVER)
async def on_hover(ls: GaitgramServer, params: types.HoverParams) -> types.Hover | None:
    if (snapshot := await ls.snapshot(params.text_document.uri)) is None:
        return None
    return hover.hover(snapshot, snapshot.positions.offset(params.position), ls.markdown)


@server.feature(types.TEXT_DOCUMENT_DEFINITION)
async def definition(ls: GaitgramServer, params: types.DefinitionParams) -> list[types.Location] | None:
    if (snapshot := await ls.snapshot(params.text_document.uri)) is None:
        return None
    return navigation.definition(snapshot, snapshot.positions.offset(params.position))


@server.feature(types.TEXT_DOCUMENT_REFERENCES)
async def references(ls: GaitgramServer, params: types.ReferenceParams) -> list[types.Location] | None:
    if (snapshot := await ls.snapshot(params.text_document.uri)) is None:
        return None
    offset = snapshot.positions.offset(params.position)
    return navigation.references(snapshot, offset, params.context.include_declaration)


@server.feature(types.TEXT_DOCUMENT_DOCUMENT_HIGHLIGHT)
async def highlight(
    ls: GaitgramServer, params: types.DocumentHighlightParams
) -> list[types.DocumentHighlight]:
    if (snapshot := await ls.snapshot(params.text_document.uri)) is None:
        return []
    return navigation.highlights(snapshot, snapshot.positions.offset(params.position))


@server.feature(types.TEXT_DOCUMENT_PREPARE_RENAME)
async def prepare_rename(
    ls: GaitgramServer, params: types.PrepareRenameParams
) -> types.PrepareRenamePlaceholder | None:
    if (snapshot := await ls.snapshot(params.text_document.uri)) is None:
        return None
    return navigation.prepare_rename(snapshot, snapshot.positions.offset(params.position))


@server.feature(types.TEXT_DOCUMENT_RENAME)
async def rename(ls: GaitgramServer, params: types.RenameParams) -> types.WorkspaceEdit | None:
    if (snapshot := await ls.snapshot(params.text_document.uri)) is None:
        return None
    return navigation.rename(snapshot, snapshot.positions.offset(params.position), params.new_name)


@server.feature(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
async def document_symbols(
    ls: GaitgramServer, params: types.DocumentSymbolParams
) -> list[types.DocumentSymbol] | list[types.SymbolInformation]:
    if (snapshot := await ls.snapshot(params.text_document.uri)) is None:
        return []
    return navigation.document_symbols(snapshot, ls.hierarchical_symbols)


@server.feature(types.WORKSPACE_SYMBOL)
async def workspace_symbols(
    ls: GaitgramServer, params: types.WorkspaceSymbolParams
) -> list[types.WorkspaceSymbol]:
    """Open grammars as they are now, and the workspace's grammar files on disk."""
    open_ = [s for document in ls.documents if (s := await ls.documents.current(document.uri)) is not None]
    roots = [f.uri for f in ls.workspace.folders.values()] or (
        [ls.workspace.root_uri] if ls.workspace.root_uri else []
    )
    paths = [p for uri in roots if (p := _path(uri))]
    on_disk = workspace_grammars(paths, skip={s.uri for s in open_})
    return navigation.workspace_symbols([*open_, *on_disk], params.query)


def _path(uri: str) -> str | None:
    from pygls.uris import to_fs_path

    return to_fs_path(uri) if uri.startswith("file:") else None


@server.feature(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL, semantic_tokens.LEGEND)
async def tokens_full(ls: GaitgramServer, params: types.SemanticTokensParams) -> types.SemanticTokens | None:
    if (snapshot := await ls.snapshot(params.text_document.uri)) is None:
        return None
    return semantic_tokens.full(snapshot)


@server.feature(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_RANGE, semantic_tokens.LEGEND)
async def tokens_range(
    ls: GaitgramServer, params: types.SemanticTokensRangeParams
) -> types.SemanticTokens | None:
    if (snapshot := await ls.snapshot(params.text_document.uri)) is None:
        return None
    span = snapshot.positions.span(params.range)
    return semantic_tokens.in_range(snapshot, span.start, span.end)


@server.feature(types.TEXT_DOCUMENT_FOLDING_RANGE)
async def folding_ranges(ls: GaitgramServer, params: types.FoldingRangeParams) -> list[types.FoldingRange]:
    if (snapshot := await ls.snapshot(params.text_document.uri)) is None:
        return []
    return folding.folding_ranges(snapshot)


@server.feature(types.TEXT_DOCUMENT_FORMATTING)
async def format_document(ls: GaitgramServer, params: types.DocumentFormattingParams) -> list[types.TextEdit]:
    if (snapshot := await ls.snapshot(params.text_document.uri)) is None:
        return []
    return formatting.formatting(snapshot)


@server.feature(types.TEXT_DOCUMENT_INLAY_HINT)
async def inlay_hint(ls: GaitgramServer, params: types.InlayHintParams) -> list[types.InlayHint]:
    if (snapshot := await ls.snapshot(params.text_document.uri)) is None:
        return []
    span = snapshot.positions.span(params.range)
    return inlay_hints.inlay_hints(snapshot, span.start, span.end)


@server.feature(
    types.TEXT_DOCUMENT_CODE_ACTION, types.CodeActionOptions(code_action_kinds=code_actions.KINDS)
)
async def code_action(ls: GaitgramServer, params: types.CodeActionParams) -> list[types.CodeAction]:
    if (snapshot := await ls.snapshot(params.text_document.uri)) is None:
        return []
    span = snapshot.positions.span(params.range)
    return code_actions.code_actions(snapshot, span.start, span.end, params.context.only)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="gaitgram-lsp", description="The gaitgram language server (stdio).")
    parser.add_argument("--tcp", metavar="HOST:PORT", help="listen on TCP instead of stdio")
    parser.add_argument("--log-level", default="WARNING", help="log to standard error from this level")
    args = parser.parse_args(argv)
    # The analysis thread holds the GIL while it works; the event loop needs it back after
    # every read and write. Handing it over every 0.5 ms instead of 5 keeps requests answered
    # within a few milliseconds during an analysis, for a few per cent of its speed.
    sys.setswitchinterval(SWITCH_INTERVAL)
    logging.basicConfig(
        level=args.log_level.upper(), format="gaitgram-lsp %(levelname)s %(name)s: %(message)s"
    )
    if args.tcp:
        host, _, port = args.tcp.rpartition(":")
        if not port.isdigit():
            parser.error(f"--tcp wants HOST:PORT, not {args.tcp!r}")
        server.start_tcp(host or "127.0.0.1", int(port))
    else:
        server.start_io()
        sys.exit(server.exit_status)
