"""Completion over the protocol: what is offered depends on where the cursor is."""

from __future__ import annotations

import pytest
from lsprotocol import types

from conftest import WALK, Client, at, doc, new_uri, open_document, published

pytestmark = pytest.mark.asyncio(loop_scope="module")


async def complete(
    client: Client, text: str, line: int, character: int | None = None, trigger: str | None = None
) -> types.CompletionList:
    uri = new_uri("completion")
    open_document(client, uri, text)
    lines = text.split("\n")
    result = await client.text_document_completion_async(
        types.CompletionParams(
            text_document=doc(uri),
            position=at(line, len(lines[line]) if character is None else character),
            context=types.CompletionContext(
                trigger_kind=types.CompletionTriggerKind.TriggerCharacter
                if trigger
                else types.CompletionTriggerKind.Invoked,
                trigger_character=trigger,
            ),
        )
    )
    assert isinstance(result, types.CompletionList)
    return result


def labels(result: types.CompletionList) -> list[str]:
    return [item.label for item in result.items]


async def test_rule_names_on_a_right_hand_side_with_their_first_production(client: Client) -> None:
    result = await complete(client, WALK + "<more> ::= <a", 7)
    assert labels(result)[:1] == ["<amp>"]
    amp = result.items[0]
    assert amp.detail == "int[0..20]"
    assert amp.kind == types.CompletionItemKind.Function
    assert amp.text_edit is not None
    assert amp.text_edit.new_text == "<amp>"
    assert amp.text_edit.range == types.Range(start=at(7, 11), end=at(7, 13))  # replaces "<a"
    everything = await complete(client, WALK + "<more> ::= x | <", 7)
    assert {"<gait>", "<hip>", "<amp>", "<unused>"} <= set(labels(everything))
    assert not any(item.kind == types.CompletionItemKind.Snippet for item in everything.items)


async def test_range_snippets_where_a_value_can_go(client: Client) -> None:
    result = await complete(client, WALK + "<more> ::= ", 7)
    snippets = [i for i in result.items if i.kind == types.CompletionItemKind.Snippet]
    assert {s.label for s in snippets} >= {"int[lo..hi]", "float[lo..hi step s]", "float[x ± p% count n]"}
    assert all(s.insert_text_format == types.InsertTextFormat.Snippet for s in snippets)  # VS Code has them
    assert "<amp>" in labels(result)


async def test_no_rule_names_where_a_new_rule_is_named(client: Client) -> None:
    result = await complete(client, WALK + "<", 7, trigger="<")
    names = labels(result)
    assert "<amp>" not in names
    assert "<gait>" not in names
    assert {"<neck>", "<missing>"} <= set(names)  # used, not defined yet
    neck = next(i for i in result.items if i.label == "<neck>")
    assert neck.text_edit is not None
    assert neck.text_edit.new_text == "<neck> ::= "
    assert "new rule" in names
    closed = await complete(client, WALK + "<ne> ::= x", 7, character=3)
    assert [i.text_edit.new_text for i in closed.items if i.label == "<neck>"] == ["<neck>"]  # type: ignore[union-attr]


async def test_annotation_names_after_at(client: Client) -> None:
    result = await complete(client, WALK + "@j", 7)
    assert set(labels(result)) == {"start", "backend", "units", "define", "joint", "frequency"}
    joint = next(i for i in result.items if i.label == "joint")
    assert joint.text_edit is not None
    assert joint.text_edit.range == types.Range(start=at(7, 1), end=at(7, 2))
    assert isinstance(joint.documentation, types.MarkupContent)
    assert "@joint elbow_fore" in joint.documentation.value


async def test_joint_names_of_the_declared_backend_after_joint(client: Client) -> None:
    result = await complete(client, WALK + "@joint ", 7, trigger=" ")
    names = labels(result)
    assert {"elbow_fore", "neck_atlas", "hip_hind"} <= set(names)
    assert len(names) == 12
    assert "<amp>" not in names
    assert names[-1] == "hip_hind"  # already driven by <hip>: offered last
    hip = next(i for i in result.items if i.label == "hip_hind")
    assert hip.detail is not None
    assert "driven by <hip>" in hip.detail
    elbow = next(i for i in result.items if i.label == "elbow_fore")
    assert elbow.detail == "forelimb, -25..60°, free from generation 11"


async def test_joint_arguments_keywords_and_limits(client: Client) -> None:
    keywords = await complete(client, WALK + "@joint elbow_fore ", 7, trigger=" ")
    assert labels(keywords) == ["limits=", "free="]
    given = await complete(client, WALK + "@joint elbow_fore free=11 ", 7, trigger=" ")
    assert labels(given) == ["limits="]
    limits = await complete(client, WALK + "@joint elbow_fore limits=", 7, trigger="=")
    assert labels(limits) == ["-25..60"]
    free = await complete(client, WALK + "@joint elbow_fore free=", 7, trigger="=")
    assert labels(free) == ["11..", "0.."]


async def test_backends_units_and_start(client: Client) -> None:
    assert {"mujoco-horse", "curve-match"} <= set(labels(await complete(client, "@backend ", 0, trigger=" ")))
    assert labels(await complete(client, "@units ", 0, trigger=" ")) == ["deg", "rad"]
    start = await complete(client, WALK.replace("@start <gait>", "@start <h"), 0)
    assert labels(start)[0] == "<hip>"


async def test_nothing_in_comments_strings_or_on_a_space_in_a_rule(client: Client) -> None:
    assert labels(await complete(client, WALK + "<more> ::= x  # see <", 7)) == []
    assert labels(await complete(client, WALK + "<more> ::= '<", 7)) == []
    assert labels(await complete(client, WALK + "<more> ::= x ", 7, trigger=" ")) == []


async def test_long_lists_are_cut_and_marked_incomplete(client: Client) -> None:
    text = "".join(f"<r{i}> ::= x\n" for i in range(500)) + "<top> ::= <r"
    result = await complete(client, text, 500)
    assert result.is_incomplete
    assert len(result.items) == 200
    narrowed = await complete(client, text + "49", 500)
    assert not narrowed.is_incomplete
    assert labels(narrowed)[0] == "<r49>"
    assert set(labels(narrowed)) == {"<r49>", *(f"<r49{i}>" for i in range(10))}


async def test_completion_answers_from_the_last_analysis_while_a_change_is_pending(client: Client) -> None:
    uri = new_uri()
    open_document(client, uri, WALK)
    await published(client, uri, 1)
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=2),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=WALK + "<more> ::= <")],
        )
    )
    result = await client.text_document_completion_async(
        types.CompletionParams(text_document=doc(uri), position=at(7, 12))
    )
    assert result is not None
    assert {"<gait>", "<amp>"} <= {item.label for item in result.items}
