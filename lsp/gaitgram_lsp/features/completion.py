"""Completion (``gaitgram.ide.completion``) as an LSP CompletionList, in the client's terms:
its position encoding, whether it takes snippets and Markdown."""

from __future__ import annotations

from dataclasses import dataclass

from lsprotocol import types

from gaitgram.ide.completion import TRIGGER_CHARACTERS, Completion, CompletionKind, CompletionModel
from gaitgram.ide.completion import complete as ide_complete
from gaitgram_lsp.positions import units

__all__ = ["TRIGGER_CHARACTERS", "Client", "CompletionModel", "complete"]

_KINDS = {
    CompletionKind.ANNOTATION: types.CompletionItemKind.Keyword,
    CompletionKind.RULE: types.CompletionItemKind.Function,
    CompletionKind.KEYWORD: types.CompletionItemKind.Property,
    CompletionKind.CHOICE: types.CompletionItemKind.EnumMember,
    CompletionKind.BACKEND: types.CompletionItemKind.Module,
    CompletionKind.VALUE: types.CompletionItemKind.Value,
    CompletionKind.SNIPPET: types.CompletionItemKind.Snippet,
    CompletionKind.SENSOR: types.CompletionItemKind.Variable,
}


@dataclass(frozen=True)
class Client:
    """What the client can show."""

    snippets: bool = False
    markdown: bool = False


def complete(
    model: CompletionModel,
    line: int,
    line_text: str,
    column: int,
    *,
    encoding: str,
    client: Client = Client(),
    trigger: str | None = None,
) -> types.CompletionList:
    """Completions at code-point ``column`` of ``line`` (whose text is ``line_text``)."""
    found = ide_complete(model, line, line_text, column, trigger)
    where = types.Range(
        start=types.Position(line=line, character=units(line_text[: found.start], encoding)),
        end=types.Position(line=line, character=units(line_text[: found.end], encoding)),
    )
    return types.CompletionList(
        is_incomplete=found.incomplete, items=[_item(item, where, client) for item in found.items]
    )


def _item(item: Completion, where: types.Range, client: Client) -> types.CompletionItem:
    snippet = item.snippet is not None and client.snippets
    documentation: types.MarkupContent | str | None = item.documentation
    if documentation is not None and client.markdown:
        documentation = types.MarkupContent(kind=types.MarkupKind.Markdown, value=documentation)
    return types.CompletionItem(
        label=item.label,
        kind=_KINDS[item.kind],
        detail=item.detail,
        documentation=documentation,
        filter_text=item.filter_text,
        sort_text=item.sort_text,
        insert_text_format=(types.InsertTextFormat.Snippet if snippet else types.InsertTextFormat.PlainText)
        if item.snippet is not None
        else None,
        text_edit=types.TextEdit(range=where, new_text=item.snippet if snippet else item.text),  # type: ignore[arg-type]
    )
