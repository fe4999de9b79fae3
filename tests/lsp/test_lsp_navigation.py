"""Hover, go to definition, references, highlights, rename and symbols over the protocol."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pygls.exceptions import JsonRpcException

from conftest import WALK, Client, at, doc, new_uri, open_document, span

pytestmark = pytest.mark.asyncio(loop_scope="module")


async def opened(client: Client, text: str = WALK) -> str:
    uri = new_uri("navigation")
    open_document(client, uri, text)
    return uri


async def hover_text(client: Client, uri: str, position: types.Position) -> str | None:
    found = await client.text_document_hover_async(
        types.HoverParams(text_document=doc(uri), position=position)
    )
    if found is None:
        return None
    assert isinstance(found.contents, types.MarkupContent)
    return found.contents.value


async def test_hover_on_a_rule_shows_productions_and_facts(client: Client) -> None:
    uri = await opened(client)
    shown = await hover_text(client, uri, at(4, 12))  # <amp> in the <hip> rule
    assert shown is not None
    assert shown.startswith("**`<amp>`**: 21 choices (reads a codon), min depth 1; productive, reachable")
    assert "<amp> ::= int[0..20]" in shown
    on_hip = await hover_text(client, uri, at(2, 13))  # <hip> in <gait>
    assert on_hip is not None
    assert "1 choice (reads no codon in lazy mode)" in on_hip
    assert "joint **hip_hind** (hindlimb)" in on_hip
    assert "backend mujoco-horse: limits -30..30 deg" in on_hip
    assert "this grammar: limits -20..30 deg" in on_hip
    assert "this grammar: free from generation 11 on" in on_hip
    unused = await hover_text(client, uri, at(6, 3))
    assert unused is not None
    assert "**unreachable**" in unused


async def test_hover_on_a_typed_range_a_joint_an_annotation_and_an_undefined_name(client: Client) -> None:
    uri = await opened(client)
    shown = await hover_text(client, uri, at(5, 14))
    assert shown is not None
    assert shown.startswith("**`int[0..20]`**: 21 values (int), first `0`, last `20`")
    joint = await hover_text(client, uri, at(3, 9))  # hip_hind in @joint
    assert joint is not None
    assert "free from generation 0 (Table 3 of the paper)" in joint
    annotation = await hover_text(client, uri, at(3, 2))
    assert annotation is not None
    assert annotation.startswith("**`@joint`** (rule): The next rule derives")
    missing = await hover_text(client, uri, at(6, 24))
    assert missing is not None
    assert "**`<missing>`** is not defined; used by <unused>" in missing
    assert "GG201 hint: define it: <missing> ::= ..." in missing
    assert await hover_text(client, uri, at(4, 20)) is None  # terminal text


async def test_definition_references_and_highlights(client: Client) -> None:
    uri = await opened(client)
    where = {"text_document": doc(uri), "position": at(4, 12)}
    definition = await client.text_document_definition_async(types.DefinitionParams(**where))
    assert isinstance(definition, list)
    assert [d.range for d in definition] == [span(at(5, 0), at(5, 5))]
    references = await client.text_document_references_async(
        types.ReferenceParams(**where, context=types.ReferenceContext(include_declaration=True))
    )
    assert [r.range.start.line for r in references] == [4, 5, 6]
    without = await client.text_document_references_async(
        types.ReferenceParams(**where, context=types.ReferenceContext(include_declaration=False))
    )
    assert [r.range.start.line for r in without] == [4, 6]
    start = await client.text_document_references_async(
        types.ReferenceParams(
            text_document=doc(uri),
            position=at(2, 2),
            context=types.ReferenceContext(include_declaration=True),
        )
    )
    assert [r.range for r in start] == [span(at(0, 7), at(0, 13)), span(at(2, 0), at(2, 6))]  # @start too
    highlights = await client.text_document_document_highlight_async(
        types.DocumentHighlightParams(text_document=doc(uri), position=at(5, 2))
    )
    assert [(h.range.start.line, h.kind) for h in highlights] == [
        (4, types.DocumentHighlightKind.Read),
        (5, types.DocumentHighlightKind.Write),
        (6, types.DocumentHighlightKind.Read),
    ]


async def test_rename_with_prepare_rename(client: Client) -> None:
    uri = await opened(client)
    prepared = await client.text_document_prepare_rename_async(
        types.PrepareRenameParams(text_document=doc(uri), position=at(5, 2))
    )
    assert isinstance(prepared, types.PrepareRenamePlaceholder)
    assert prepared.range == span(at(5, 1), at(5, 4))
    assert prepared.placeholder == "amp"
    assert (
        await client.text_document_prepare_rename_async(
            types.PrepareRenameParams(text_document=doc(uri), position=at(4, 20))
        )
        is None
    )
    edit = await client.text_document_rename_async(
        types.RenameParams(text_document=doc(uri), position=at(5, 2), new_name="amplitude")
    )
    assert edit is not None
    assert edit.changes is not None
    assert [(e.range.start.line, e.new_text) for e in edit.changes[uri]] == [
        (4, "amplitude"),
        (5, "amplitude"),
        (6, "amplitude"),
    ]
    gait = await client.text_document_rename_async(
        types.RenameParams(text_document=doc(uri), position=at(2, 2), new_name="<walk>")
    )
    assert gait is not None
    assert gait.changes is not None
    assert [e.range for e in gait.changes[uri]] == [span(at(0, 8), at(0, 12)), span(at(2, 1), at(2, 5))]


@pytest.mark.parametrize(
    ("new_name", "reason"),
    [
        ("two words", "is not a rule name"),
        ("a|b", "is not a rule name"),
        ("", "is not a rule name"),
        ("hip", "is already defined"),
    ],
)
async def test_rename_refuses_invalid_names(client: Client, new_name: str, reason: str) -> None:
    uri = await opened(client)
    with pytest.raises(JsonRpcException, match=reason):
        await client.text_document_rename_async(
            types.RenameParams(text_document=doc(uri), position=at(5, 2), new_name=new_name)
        )


async def test_document_symbols(client: Client) -> None:
    uri = await opened(client)
    symbols = await client.text_document_document_symbol_async(
        types.DocumentSymbolParams(text_document=doc(uri))
    )
    assert symbols is not None
    assert [(s.name, s.detail) for s in symbols] == [  # type: ignore[union-attr]
        ("@start", "<gait>"),
        ("@backend", "mujoco-horse"),
        ("<gait>", "1 choice"),
        ("<hip>", "joint hip_hind, 1 choice"),
        ("<amp>", "21 choices"),
        ("<unused>", "2 choices"),
    ]
    hip = symbols[3]
    assert isinstance(hip, types.DocumentSymbol)
    assert hip.range == span(at(3, 0), at(4, 27))  # with its @joint line
    assert hip.selection_range == span(at(4, 0), at(4, 5))


async def test_workspace_symbols_cover_open_documents_and_files_on_disk(client: Client) -> None:
    uri = await opened(client, "<disk_like> ::= x\n")
    found = await client.workspace_symbol_async(types.WorkspaceSymbolParams(query="disk"))
    assert found is not None
    by_name = {s.name: s.location.uri for s in found}  # type: ignore[union-attr]
    disk = (client.workspace_folder / "on_disk.gg").as_uri()  # type: ignore[attr-defined]
    assert by_name["<disk_like>"] == uri
    assert by_name["<disk_rule>"] == disk
    assert by_name["<disk_other>"] == disk
    fuzzy = await client.workspace_symbol_async(types.WorkspaceSymbolParams(query="dsko"))
    assert fuzzy is not None
    assert {s.name for s in fuzzy} == {"<disk_other>"}
