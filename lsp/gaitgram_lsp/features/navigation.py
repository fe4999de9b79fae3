"""Rule names (``gaitgram.ide.navigation``) as LSP locations, highlights, edits and symbols."""

from __future__ import annotations

from collections.abc import Iterable

from lsprotocol import types
from pygls.exceptions import JsonRpcException

from gaitgram.ide import navigation
from gaitgram.ide.navigation import SymbolKind
from gaitgram_lsp.documents import Snapshot

#: Workspace symbol answers are cut here.
MAX_WORKSPACE_SYMBOLS = 1_000

_SYMBOL_KINDS = {SymbolKind.RULE: types.SymbolKind.Function, SymbolKind.SETTING: types.SymbolKind.Property}


def _occurrences(snapshot: Snapshot, offset: int) -> list[navigation.Occurrence]:
    grammar = snapshot.result.grammar
    found = navigation.name_at(grammar, offset)
    return [] if found is None else navigation.occurrences(grammar, found.name)


def definition(snapshot: Snapshot, offset: int) -> list[types.Location] | None:
    heads = [o for o in _occurrences(snapshot, offset) if o.definition]
    return [types.Location(uri=snapshot.uri, range=snapshot.positions.range(o.span)) for o in heads] or None


def references(snapshot: Snapshot, offset: int, include_declaration: bool = True) -> list[types.Location]:
    return [
        types.Location(uri=snapshot.uri, range=snapshot.positions.range(o.span))
        for o in _occurrences(snapshot, offset)
        if include_declaration or not o.definition
    ]


def highlights(snapshot: Snapshot, offset: int) -> list[types.DocumentHighlight]:
    return [
        types.DocumentHighlight(
            range=snapshot.positions.range(o.span),
            kind=types.DocumentHighlightKind.Write if o.definition else types.DocumentHighlightKind.Read,
        )
        for o in _occurrences(snapshot, offset)
    ]


class RenameRefused(JsonRpcException):
    """Sent to the client as an error response (LSP's RequestFailed), with the reason."""

    CODE = -32803


def prepare_rename(snapshot: Snapshot, offset: int) -> types.PrepareRenamePlaceholder | None:
    found = navigation.rename_target(snapshot.result.grammar, offset)
    if found is None:
        return None
    name, span = found
    return types.PrepareRenamePlaceholder(range=snapshot.positions.range(span), placeholder=name)


def rename(snapshot: Snapshot, offset: int, new_name: str) -> types.WorkspaceEdit:
    try:
        edits = navigation.rename(snapshot.result.grammar, offset, new_name)
    except navigation.RenameRefused as refused:
        raise RenameRefused(str(refused)) from None
    return types.WorkspaceEdit(
        changes={
            snapshot.uri: [
                types.TextEdit(range=snapshot.positions.range(e.span), new_text=e.text) for e in edits
            ]
        }
    )


def document_symbols(
    snapshot: Snapshot, hierarchical: bool = True
) -> list[types.DocumentSymbol] | list[types.SymbolInformation]:
    found = navigation.symbols(snapshot.result)
    positions = snapshot.positions
    if hierarchical:
        return [
            types.DocumentSymbol(
                name=s.name,
                kind=_SYMBOL_KINDS[s.kind],
                detail=s.detail or None,
                range=positions.range(s.span),
                selection_range=positions.range(s.selection),
            )
            for s in found
        ]
    return [
        types.SymbolInformation(
            name=s.name,
            kind=_SYMBOL_KINDS[s.kind],
            location=types.Location(uri=snapshot.uri, range=positions.range(s.selection)),
        )
        for s in found
    ]


def workspace_symbols(snapshots: Iterable[Snapshot], query: str) -> list[types.WorkspaceSymbol]:
    """Rules of every grammar given (open and on disk) whose names match ``query``."""
    by_grammar = {id(s.result.grammar): s for s in snapshots}
    grammars = [s.result.grammar for s in by_grammar.values()]
    return [
        types.WorkspaceSymbol(
            name=f"<{rule.name}>",
            kind=types.SymbolKind.Function,
            location=types.Location(
                uri=(snapshot := by_grammar[id(grammar)]).uri,
                range=snapshot.positions.range(rule.name_span),
            ),
            container_name=snapshot.uri.rsplit("/", 1)[-1],
        )
        for grammar, rule in navigation.rules_matching(grammars, query, MAX_WORKSPACE_SYMBOLS)
    ]
