"""Diagnostics over the protocol: exactly ``gaitgram check``'s, pushed per version, never stale,
and pulled by clients that pull."""

from __future__ import annotations

import asyncio

import pytest
import pytest_lsp
from lsprotocol import types

from conftest import (
    CONFIG,
    WALK,
    Client,
    at,
    capabilities,
    doc,
    edit,
    expected,
    new_uri,
    open_document,
    published,
    replace_all,
    seen,
    span,
)

pytestmark = pytest.mark.asyncio(loop_scope="module")


async def test_diagnostics_on_open_are_gaitgram_checks(client: Client) -> None:
    uri = new_uri()
    open_document(client, uri, WALK)
    found = await published(client, uri, 1)
    assert seen(found) == expected(WALK)
    assert {d.source for d in found} == {"gaitgram"}
    undefined = next(d for d in found if d.message == "<missing> is not defined")
    assert undefined.range == span(at(6, 21), at(6, 30))  # <missing>
    assert undefined.severity == types.DiagnosticSeverity.Error
    unreachable = next(d for d in found if d.code == "GG204")
    assert list(unreachable.tags or []) == [types.DiagnosticTag.Unnecessary]


async def test_diagnostics_follow_whole_and_incremental_changes(client: Client) -> None:
    uri = new_uri()
    open_document(client, uri, WALK)
    await published(client, uri, 1)
    fixed = WALK.replace("<hip>;<neck>", "<hip>").replace(" | <missing>", "")
    replace_all(client, uri, 2, fixed)
    assert seen(await published(client, uri, 2)) == expected(fixed)
    # an incremental edit: <amp> ::= int[0..20] becomes <amp> ::= int[0..2O] (a typo)
    edit(client, uri, 3, span(at(5, 18), at(5, 19)), "O")
    broken = fixed.replace("int[0..20]", "int[0..2O]")
    found = await published(client, uri, 3)
    assert seen(found) == expected(broken)
    assert "GG104" in {d.code for d in found}


async def test_a_burst_of_edits_is_checked_once_and_never_published_stale(client: Client) -> None:
    uri = new_uri()
    open_document(client, uri, WALK)
    await published(client, uri, 1)
    text = WALK
    for version, typed in enumerate("<extra> ::", start=2):  # typed one character at a time
        line = text.count("\n")
        column = len(text) - text.rfind("\n") - 1
        edit(client, uri, version, span(at(line, column), at(line, column)), typed)
        text += typed
    final = await published(client, uri, 11)
    assert seen(final) == expected(text)
    # One more edit, and its diagnostics: a document's analyses run one after another, so once
    # version 12's are out, every analysis of an older text has finished (and was dropped, or
    # shows below).
    end = at(text.count("\n"), len(text) - text.rfind("\n") - 1)
    edit(client, uri, 12, span(end, end), " x")
    await published(client, uri, 12)
    versions = [p.version for p in client.published if p.uri == uri]
    assert versions == sorted(versions)  # never an older version after a newer one
    assert versions[-2:] == [11, 12]  # nothing between: no stale version after the last
    assert len(versions) < 12  # debounced: not one check per keystroke


async def test_closing_a_document_clears_its_diagnostics(client: Client) -> None:
    uri = new_uri()
    open_document(client, uri, WALK)
    assert await published(client, uri, 1)
    client.text_document_did_close(types.DidCloseTextDocumentParams(text_document=doc(uri)))
    for _ in range(200):
        if client.published[-1].uri == uri and not client.published[-1].diagnostics:
            break
        await asyncio.sleep(0.01)
    assert list(client.diagnostics[uri]) == []


async def test_define_values_reach_ge_range_across_edits(client: Client) -> None:
    uri = new_uri()
    text = "<a> ::= <b> | GE_RANGE:n\n<b> ::= x\n"
    open_document(client, uri, text)
    assert [d.code for d in await published(client, uri, 1)] == ["GG405"]
    edit(client, uri, 2, span(at(0, 0), at(0, 0)), "@define n=3\n")  # a new segment above
    assert seen(await published(client, uri, 2)) == expected("@define n=3\n" + text) == []
    edit(client, uri, 3, span(at(0, 10), at(0, 11)), "0")  # n=0 is out of range: GG105
    assert seen(await published(client, uri, 3)) == expected("@define n=0\n" + text)


# ---- a client that pulls diagnostics (Neovim 0.10 declares it) -------------------------------


@pytest_lsp.fixture(scope="module", config=CONFIG)
async def pulling(lsp_client: Client):
    await lsp_client.initialize_session(types.InitializeParams(capabilities=capabilities("neovim@v0.10.0")))
    yield
    await lsp_client.shutdown_session()


async def test_pull_diagnostics_and_result_ids(pulling: Client) -> None:
    uri = new_uri()
    open_document(pulling, uri, WALK)
    report = await pulling.text_document_diagnostic_async(
        types.DocumentDiagnosticParams(text_document=doc(uri))
    )
    assert isinstance(report, types.RelatedFullDocumentDiagnosticReport)
    assert seen(report.items) == expected(WALK)
    again = await pulling.text_document_diagnostic_async(
        types.DocumentDiagnosticParams(text_document=doc(uri), previous_result_id=report.result_id)
    )
    assert isinstance(again, types.RelatedUnchangedDocumentDiagnosticReport)
    fixed = WALK.replace(" | <missing>", "")
    replace_all(pulling, uri, 2, fixed)
    changed = await pulling.text_document_diagnostic_async(
        types.DocumentDiagnosticParams(text_document=doc(uri), previous_result_id=report.result_id)
    )
    assert isinstance(changed, types.RelatedFullDocumentDiagnosticReport)
    assert seen(changed.items) == expected(fixed)
    # A push of a text's diagnostics would go out as its analysis finishes, before the answer to a
    # pull waiting on it; one more edit and pull, whose answer comes after every analysis of the
    # texts before it, and after anything pushed of them.
    replace_all(pulling, uri, 3, WALK)
    last = await pulling.text_document_diagnostic_async(
        types.DocumentDiagnosticParams(text_document=doc(uri))
    )
    assert isinstance(last, types.RelatedFullDocumentDiagnosticReport)
    assert seen(last.items) == expected(WALK)
    assert not [p for p in pulling.published if p.uri == uri]  # a pulling client is not also pushed to


async def test_a_lone_surrogate_sent_as_a_json_escape_is_gg109(client: Client) -> None:
    """JSON may carry ``\\ud800`` alone, which no file can hold: the server reports it where it
    is (one UTF-16 unit) instead of failing to encode its answer."""
    uri = new_uri()
    text = "<a> ::= '\ud800' | b\n"
    open_document(client, uri, text)
    found = await published(client, uri, 1)
    assert seen(found) == expected(text)
    (lone,) = [d for d in found if d.code == "GG109"]
    assert lone.range == span(at(0, 9), at(0, 10))
    assert lone.severity == types.DiagnosticSeverity.Error
