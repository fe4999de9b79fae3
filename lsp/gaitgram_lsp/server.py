"""The gaitgram language server: registers features; each handler converts and delegates.

The logic lives in :mod:`gaitgram_lsp.features` (pure functions of the text); here
only LSP positions (UTF-16 columns) and types are handled.
"""

from __future__ import annotations

import argparse
import asyncio

from lsprotocol import types
from pygls.lsp.server import LanguageServer

from gaitgram import __version__
from gaitgram.diagnostics import Severity
from gaitgram.language.source import SourceText, Span
from gaitgram_lsp import features

server = LanguageServer("gaitgram-lsp", __version__)

_SEVERITY = {
    Severity.ERROR: types.DiagnosticSeverity.Error,
    Severity.WARNING: types.DiagnosticSeverity.Warning,
    Severity.INFO: types.DiagnosticSeverity.Information,
}
_KIND = {
    "rule": types.CompletionItemKind.Reference,
    "annotation": types.CompletionItemKind.Keyword,
    "joint": types.CompletionItemKind.EnumMember,
    "backend": types.CompletionItemKind.Module,
}


def _utf16(text: str) -> int:
    return len(text.encode("utf-16-le")) // 2


def to_position(source: SourceText, offset: int) -> types.Position:
    location = source.location(offset)
    prefix = source.line_text(location.line)[: location.column - 1]
    return types.Position(line=location.line - 1, character=_utf16(prefix))


def to_range(source: SourceText, span: Span) -> types.Range:
    return types.Range(start=to_position(source, span.start), end=to_position(source, span.end))


def from_position(text: str, position: types.Position) -> tuple[int, int]:
    """(line, code-point column) from an LSP position."""
    lines = text.split("\n")
    line = lines[position.line] if position.line < len(lines) else ""
    units, column = 0, 0
    for ch in line:
        if units >= position.character:
            break
        units += 2 if ord(ch) > 0xFFFF else 1
        column += 1
    return position.line, column


#: The last completed analysis per document: completion answers from it without waiting.
LATEST: dict[str, features.CheckResult] = {}
#: Edits arriving within this many seconds are checked once, for the last of them.
DEBOUNCE_SECONDS = 0.05
_LOCKS: dict[str, asyncio.Lock] = {}
#: Completion lists are cut here (the client asks again as the user types: is_incomplete).
MAX_COMPLETIONS = 200


async def publish_later(uri: str, version: int | None) -> None:
    """Debounced, off the event loop: a large document's check never blocks completion, and
    a result for a superseded version is dropped, never published."""
    await asyncio.sleep(DEBOUNCE_SECONDS)
    async with _LOCKS.setdefault(uri, asyncio.Lock()):  # one analysis at a time: no pile-up
        document = server.workspace.get_text_document(uri)
        if version is not None and document.version != version:
            return  # a newer edit has arrived; its own task will publish
        text = document.source
        result = await asyncio.to_thread(features.analysed, text)
        document = server.workspace.get_text_document(uri)
        if version is not None and document.version != version:
            return
        LATEST[uri] = result
        publish(uri, version, result)


def _diagnostics(result: features.CheckResult) -> list[types.Diagnostic]:
    source = result.grammar.source
    return [
        types.Diagnostic(
            range=to_range(source, d.span),
            message=d.message + (f"\nhint: {d.hint}" if d.hint else ""),
            severity=_SEVERITY[d.level],
            code=d.code.code,
            source="gaitgram",
        )
        for d in result.diagnostics
    ]


def publish(uri: str, version: int | None, result: features.CheckResult) -> None:
    server.text_document_publish_diagnostics(
        types.PublishDiagnosticsParams(uri=uri, diagnostics=_diagnostics(result), version=version)
    )


@server.feature(types.TEXT_DOCUMENT_DID_OPEN)
async def did_open(ls: LanguageServer, params: types.DidOpenTextDocumentParams) -> None:
    await publish_later(params.text_document.uri, params.text_document.version)


@server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
async def did_change(ls: LanguageServer, params: types.DidChangeTextDocumentParams) -> None:
    await publish_later(params.text_document.uri, params.text_document.version)


@server.feature(types.TEXT_DOCUMENT_COMPLETION, types.CompletionOptions(trigger_characters=["<", "@", " "]))
def completion(ls: LanguageServer, params: types.CompletionParams) -> types.CompletionList:
    text = ls.workspace.get_text_document(params.text_document.uri).source
    line, column = from_position(text, params.position)
    found = features.completions(text, line, column, LATEST.get(params.text_document.uri))
    items = [
        types.CompletionItem(label=c.label, kind=_KIND[c.kind], detail=c.detail or None)
        for c in found[:MAX_COMPLETIONS]
    ]
    if not found or found[0].kind == "rule":  # snippets where rules or new rules are written
        items += [
            types.CompletionItem(
                label=label,
                kind=types.CompletionItemKind.Snippet,
                detail=detail,
                insert_text=body,
                insert_text_format=types.InsertTextFormat.Snippet,
            )
            for label, (body, detail) in features.SNIPPETS.items()
        ]
    return types.CompletionList(is_incomplete=len(found) > MAX_COMPLETIONS, items=items)


@server.feature(types.TEXT_DOCUMENT_HOVER)
def hover(ls: LanguageServer, params: types.HoverParams) -> types.Hover | None:
    text = ls.workspace.get_text_document(params.text_document.uri).source
    position = from_position(text, params.position)
    found = features.range_hover(text, *position) or features.hover(text, *position)
    if found is None:
        return None
    return types.Hover(contents=types.MarkupContent(kind=types.MarkupKind.Markdown, value=found))


@server.feature(types.TEXT_DOCUMENT_DEFINITION)
def definition(ls: LanguageServer, params: types.DefinitionParams) -> types.Location | None:
    text = ls.workspace.get_text_document(params.text_document.uri).source
    span = features.definition(text, *from_position(text, params.position))
    if span is None:
        return None
    source = features.analysed(text).grammar.source
    return types.Location(uri=params.text_document.uri, range=to_range(source, span))


@server.feature(types.TEXT_DOCUMENT_REFERENCES)
def references(ls: LanguageServer, params: types.ReferenceParams) -> list[types.Location]:
    text = ls.workspace.get_text_document(params.text_document.uri).source
    source = features.analysed(text).grammar.source
    return [
        types.Location(uri=params.text_document.uri, range=to_range(source, span))
        for span in features.references(text, *from_position(text, params.position))
    ]


def _text(ls: LanguageServer, uri: str) -> str:
    return ls.workspace.get_text_document(uri).source


def _edit(source: SourceText, span: Span, new_text: str) -> types.TextEdit:
    return types.TextEdit(range=to_range(source, span), new_text=new_text)


@server.feature(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
def document_symbols(ls: LanguageServer, params: types.DocumentSymbolParams) -> list[types.DocumentSymbol]:
    text = _text(ls, params.text_document.uri)
    source = features.analysed(text).grammar.source
    return [
        types.DocumentSymbol(
            name=f"<{s.name}>",
            kind=types.SymbolKind.Function,
            detail=s.detail,
            range=to_range(source, s.span),
            selection_range=to_range(source, s.name_span),
        )
        for s in features.document_symbols(text)
    ]


@server.feature(types.TEXT_DOCUMENT_FOLDING_RANGE)
def folding(ls: LanguageServer, params: types.FoldingRangeParams) -> list[types.FoldingRange]:
    return [
        types.FoldingRange(start_line=a, end_line=b)
        for a, b in features.folding_ranges(_text(ls, params.text_document.uri))
    ]


@server.feature(types.TEXT_DOCUMENT_DOCUMENT_HIGHLIGHT)
def highlight(ls: LanguageServer, params: types.DocumentHighlightParams) -> list[types.DocumentHighlight]:
    text = _text(ls, params.text_document.uri)
    source = features.analysed(text).grammar.source
    return [
        types.DocumentHighlight(range=to_range(source, span))
        for span in features.references(text, *from_position(text, params.position))
    ]


@server.feature(types.TEXT_DOCUMENT_PREPARE_RENAME)
def prepare_rename(ls: LanguageServer, params: types.PrepareRenameParams) -> types.Range | None:
    text = _text(ls, params.text_document.uri)
    span = features.prepare_rename(text, *from_position(text, params.position))
    return None if span is None else to_range(features.analysed(text).grammar.source, span)


@server.feature(types.TEXT_DOCUMENT_RENAME)
def rename(ls: LanguageServer, params: types.RenameParams) -> types.WorkspaceEdit:
    text = _text(ls, params.text_document.uri)
    try:
        edits = features.rename(text, *from_position(text, params.position), params.new_name)
    except features.RenameError as error:
        raise ValueError(str(error)) from None  # pygls reports it to the client as an error response
    source = features.analysed(text).grammar.source
    return types.WorkspaceEdit(changes={params.text_document.uri: [_edit(source, s, t) for s, t in edits]})


@server.feature(types.TEXT_DOCUMENT_FORMATTING)
def formatting(ls: LanguageServer, params: types.DocumentFormattingParams) -> list[types.TextEdit]:
    from gaitgram.language.formatter import FormatError, FormatRefused, format_text

    text = _text(ls, params.text_document.uri)
    try:
        formatted = format_text(text)
    except (FormatRefused, FormatError):
        return []  # syntax errors: the layout may carry meaning, so change nothing
    if formatted == text:
        return []
    source = SourceText(text)
    return [_edit(source, Span(0, len(source.text)), formatted)]


@server.feature(types.TEXT_DOCUMENT_CODE_ACTION)
def code_action(ls: LanguageServer, params: types.CodeActionParams) -> list[types.CodeAction]:
    uri = params.text_document.uri
    text = _text(ls, uri)
    source = features.analysed(text).grammar.source
    start = source.offset(*[v + 1 for v in from_position(text, params.range.start)])
    end = source.offset(*[v + 1 for v in from_position(text, params.range.end)])
    return [
        types.CodeAction(
            title=fix.title,
            kind=types.CodeActionKind.QuickFix,
            edit=types.WorkspaceEdit(changes={uri: [_edit(source, s, t) for s, t in fix.edits]}),
        )
        for fix in [*features.code_actions(text, start, end), *features.range_refactors(text, start)]
    ]


@server.feature(types.TEXT_DOCUMENT_INLAY_HINT)
def inlay_hint(ls: LanguageServer, params: types.InlayHintParams) -> list[types.InlayHint]:
    text = _text(ls, params.text_document.uri)
    source = features.analysed(text).grammar.source
    return [
        types.InlayHint(position=to_position(source, offset), label=label)
        for offset, label in features.inlay_hints(text)
    ]


@server.feature(
    types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL,
    types.SemanticTokensLegend(token_types=list(features.TOKEN_TYPES), token_modifiers=[]),
)
def semantic_tokens(ls: LanguageServer, params: types.SemanticTokensParams) -> types.SemanticTokens:
    text = _text(ls, params.text_document.uri)
    source = SourceText(text)
    data: list[int] = []
    previous_line = previous_start = 0
    for start, length, kind in features.semantic_tokens(source.text):
        position = to_position(source, start)
        end = to_position(source, start + length)
        if end.line != position.line:  # multi-line tokens are not allowed: keep the first line
            length_units = (
                len(source.line_text(position.line + 1).encode("utf-16-le")) // 2 - position.character
            )
        else:
            length_units = end.character - position.character
        delta_line = position.line - previous_line
        delta_start = position.character - previous_start if delta_line == 0 else position.character
        data += [delta_line, delta_start, length_units, features.TOKEN_TYPES.index(kind), 0]
        previous_line, previous_start = position.line, position.character
    return types.SemanticTokens(data=data)


@server.feature(
    types.TEXT_DOCUMENT_DIAGNOSTIC,
    types.DiagnosticOptions(inter_file_dependencies=False, workspace_diagnostics=False),
)
def pull_diagnostics(
    ls: LanguageServer, params: types.DocumentDiagnosticParams
) -> types.FullDocumentDiagnosticReport:
    text = _text(ls, params.text_document.uri)
    return types.FullDocumentDiagnosticReport(items=_diagnostics(features.analysed(text)))


@server.feature(types.WORKSPACE_SYMBOL)
def workspace_symbols(ls: LanguageServer, params: types.WorkspaceSymbolParams) -> list[types.WorkspaceSymbol]:
    found = []
    for uri, document in list(ls.workspace.text_documents.items()):
        source = features.analysed(document.source).grammar.source
        for symbol in features.document_symbols(document.source):
            if params.query.lower() in symbol.name.lower():
                found.append(
                    types.WorkspaceSymbol(
                        name=f"<{symbol.name}>",
                        kind=types.SymbolKind.Function,
                        location=types.Location(uri=uri, range=to_range(source, symbol.name_span)),
                    )
                )
    return found


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="gaitgram-lsp", description="The gaitgram language server.")
    parser.add_argument("--tcp", metavar="HOST:PORT", help="listen on TCP instead of stdio")
    args = parser.parse_args(argv)
    if args.tcp:
        host, _, port = args.tcp.rpartition(":")
        server.start_tcp(host or "127.0.0.1", int(port))
    else:
        server.start_io()
