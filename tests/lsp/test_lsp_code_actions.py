"""Code actions over the protocol, applied to the text and checked again with ``gaitgram check``."""

from __future__ import annotations

import pytest
from lsprotocol import types

from conftest import Client, at, doc, new_uri, open_document, span
from gaitgram.analysis import check
from gaitgram.language import parse

pytestmark = pytest.mark.asyncio(loop_scope="module")


def apply(text: str, edits: list[types.TextEdit]) -> str:
    """Apply LSP edits to (ASCII) text, last first."""
    lines = text.split("\n")

    def offset(position: types.Position) -> int:
        return sum(len(line) + 1 for line in lines[: position.line]) + position.character

    for edit in sorted(edits, key=lambda e: offset(e.range.start), reverse=True):
        text = text[: offset(edit.range.start)] + edit.new_text + text[offset(edit.range.end) :]
    return text


async def actions(
    client: Client,
    text: str,
    start: types.Position,
    end: types.Position | None = None,
    only: list[str] | None = None,
) -> tuple[str, dict[str, types.CodeAction]]:
    uri = new_uri("actions")
    open_document(client, uri, text)
    found = await client.text_document_code_action_async(
        types.CodeActionParams(
            text_document=doc(uri),
            range=span(start, end or start),
            context=types.CodeActionContext(diagnostics=[], only=only),
        )
    )
    return uri, {a.title: a for a in found or [] if isinstance(a, types.CodeAction)}


def applied(text: str, uri: str, action: types.CodeAction) -> str:
    assert action.edit is not None
    assert action.edit.changes is not None
    return apply(text, list(action.edit.changes[uri]))


def codes(text: str) -> list[str]:
    return [d.code.code for d in check(parse(text)).diagnostics]


async def test_define_a_missing_rule_or_use_the_nearest_name(client: Client) -> None:
    text = "<a> ::= <b> | <bee>\n<b> ::= x\n<beef> ::= y\n"
    uri, found = await actions(client, text, at(0, 16))
    assert list(found) == ["Define <bee>", "Replace with <beef>"]
    replace = found["Replace with <beef>"]
    assert replace.kind == types.CodeActionKind.QuickFix
    assert replace.is_preferred
    assert [d.code for d in replace.diagnostics or []] == ["GG201"]
    assert applied(text, uri, replace) == "<a> ::= <b> | <beef>\n<b> ::= x\n<beef> ::= y\n"
    defined = applied(text, uri, found["Define <bee>"])
    assert defined == "<a> ::= <b> | <bee>\n<bee> ::= ''\n<b> ::= x\n<beef> ::= y\n"
    assert "GG201" not in codes(defined)


async def test_remove_unreachable_rules(client: Client) -> None:
    text = "<a> ::= x\n@joint hip_hind\n<lost> ::= y  # gone too\n  | z\n<also> ::= w\n"
    uri, found = await actions(client, text, at(2, 2))
    assert "Remove unreachable <lost>" in found
    removed = applied(text, uri, found["Remove unreachable <lost>"])
    assert removed == "<a> ::= x\n<also> ::= w\n"
    everything = applied(text, uri, found["Remove all 2 unreachable rules"])
    assert everything == "<a> ::= x\n"
    assert codes(everything) == []


async def test_replace_an_unknown_annotation_or_joint(client: Client) -> None:
    text = "@backend mujoco-horse\n@jont hip_hind\n<a> ::= x\n@joint hip_hnd\n<b> ::= y\n"
    uri, found = await actions(client, text, at(1, 2))
    assert applied(text, uri, found["Replace with @joint"]).startswith(
        "@backend mujoco-horse\n@joint hip_hind\n"
    )
    uri, found = await actions(client, text, at(3, 9))
    assert "@joint hip_hind\n<b> ::= y" in applied(text, uri, found["Replace with hip_hind"])


async def test_collapse_a_value_list_into_a_typed_range_and_expand_it_back(client: Client) -> None:
    text = "<a> ::= <amp>\n<amp> ::= 0 | 0.25 | 0.5 | 0.75 | 1 | 1.25 | 1.5 | 1.75 | 2\n"
    uri, found = await actions(client, text, at(1, 3))
    collapse = found["Collapse 9 values into float[0..2 step 0.25]"]
    assert collapse.kind == types.CodeActionKind.RefactorRewrite
    collapsed = applied(text, uri, collapse)
    assert collapsed == "<a> ::= <amp>\n<amp> ::= float[0..2 step 0.25]\n"
    uri, back = await actions(client, collapsed, at(1, 15))
    assert applied(collapsed, uri, back["Expand float[0..2 step 0.25] into its 9 values"]) == text
    ints = "<k> ::= x | 1 | 2 | 3 | 4 | y\n"
    uri, found = await actions(client, ints, at(0, 2))
    assert applied(ints, uri, found["Collapse 4 values into int[1..4]"]) == "<k> ::= x | int[1..4] | y\n"


@pytest.mark.parametrize(
    "rule",
    [
        "<k> ::= 1 | 2 | 4\n",  # not evenly spaced
        "<k> ::= 0 | 0.50 | 1\n",  # float[0..1 step 0.5] derives 0.5, not 0.50
        "<k> ::= 1 | 2\n",  # too short to be worth it
        "<k> ::= 1 | 2 # one\n | 3\n",  # a comment would be lost
    ],
)
async def test_no_collapse_that_would_change_meaning_or_lose_text(client: Client, rule: str) -> None:
    _, found = await actions(client, rule, at(0, 2))
    assert not [title for title in found if title.startswith("Collapse")]


async def test_only_the_kinds_asked_for(client: Client) -> None:
    text = "<a> ::= <b> | 0 | 1 | 2\n"
    _, everything = await actions(client, text, at(0, 9))
    assert {"Define <b>", "Collapse 3 values into int[0..2]"} <= set(everything)
    _, fixes = await actions(client, text, at(0, 9), only=[types.CodeActionKind.QuickFix])
    assert "Collapse 3 values into int[0..2]" not in fixes
    assert "Define <b>" in fixes
    _, refactors = await actions(client, text, at(0, 9), only=[types.CodeActionKind.Refactor])
    assert list(refactors) == ["Collapse 3 values into int[0..2]"]


async def test_quick_fixes_are_the_fixes_the_diagnostics_carry(client: Client) -> None:
    text = "<a> ::= flaot[0..1 step 0.5] | x | | y | | z\n"
    uri, found = await actions(client, text, at(0, 10))
    look_alike = found["Make it the range float[0..1 step 0.5]"]
    assert look_alike.is_preferred
    assert [d.code for d in look_alike.diagnostics or []] == ["GG309"]
    assert applied(text, uri, look_alike) == "<a> ::= float[0..1 step 0.5] | x | | y | | z\n"
    expected = {d.code.code: [f.title for f in d.fixes] for d in check(parse(text)).diagnostics}
    assert expected["GG309"] == ["Make it the range float[0..1 step 0.5]"]
    uri, found = await actions(client, text, at(0, 35))
    assert (
        applied(text, uri, found["Fix all 2 GG106 problems"]) == "<a> ::= flaot[0..1 step 0.5] | x | y | z\n"
    )
