"""The language server on a generated 5,000-rule document, measured over the protocol.

Completion latency (p50/p95 of 50 requests, each right after an edit) and the time from a
change to its diagnostics being published, against a baseline measured in the same run:
plain ``check(parse(text))`` of the document in-process. Targets: completion p95 < 50 ms,
diagnostics < 300 ms after a change.
"""

from __future__ import annotations

import asyncio
import statistics
import sys
import time

from lsprotocol import types
from pygls.lsp.client import LanguageClient

from benchmarks._timing import measure
from benchmarks.bench_check import generated_grammar
from gaitgram.analysis import check
from gaitgram.language import parse

URI = "file:///bench/big.gg"


async def run() -> None:
    text = generated_grammar(5_000)
    baseline = measure(lambda: check(parse(text)), runs=3, min_time=0.0)
    published: dict[int, float] = {}
    client = LanguageClient("gaitgram-bench", "1")

    @client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def on_diagnostics(params: types.PublishDiagnosticsParams) -> None:
        if params.version is not None:
            published[params.version] = time.perf_counter()

    await client.start_io(sys.executable, "-m", "gaitgram_lsp")
    await client.initialize_async(types.InitializeParams(capabilities=types.ClientCapabilities()))
    client.initialized(types.InitializedParams())
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(uri=URI, language_id="gaitgram", version=1, text=text)
        )
    )
    while 1 not in published:
        await asyncio.sleep(0.01)

    lines = text.split("\n")
    completion_ms, diagnostics_ms = [], []
    for version in range(2, 52):
        edited = f"<r{version}> ::= x | <r{version + 1}>"
        lines[version] = edited
        text = "\n".join(lines)
        sent = time.perf_counter()
        client.text_document_did_change(
            types.DidChangeTextDocumentParams(
                text_document=types.VersionedTextDocumentIdentifier(uri=URI, version=version),
                content_changes=[types.TextDocumentContentChangeWholeDocument(text=text)],
            )
        )
        start = time.perf_counter()
        await client.text_document_completion_async(
            types.CompletionParams(
                text_document=types.TextDocumentIdentifier(uri=URI),
                position=types.Position(line=version, character=len(edited)),
            )
        )
        completion_ms.append((time.perf_counter() - start) * 1e3)
        if version % 5 == 0:  # let some changes settle to measure their diagnostics
            while version not in published:
                await asyncio.sleep(0.002)
            diagnostics_ms.append((published[version] - sent) * 1e3)
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()

    p95 = statistics.quantiles(completion_ms, n=20)[-1]
    print(
        f"5,000-rule document ({len(text) / 1e3:.0f} KB); baseline check(parse(text)) in-process: "
        f"{baseline.median * 1e3:.0f} ms"
    )
    print(
        f"completion after an edit   p50 {statistics.median(completion_ms):6.1f} ms   p95 {p95:6.1f} ms"
        "   (target p95 < 50 ms)"
    )
    print(
        f"diagnostics after a change p50 {statistics.median(diagnostics_ms):6.1f} ms   "
        f"max {max(diagnostics_ms):6.1f} ms   (target < 300 ms; "
        f"ratio to the baseline {statistics.median(diagnostics_ms) / (baseline.median * 1e3):.2f}x)"
    )


def main() -> None:
    asyncio.run(run())
